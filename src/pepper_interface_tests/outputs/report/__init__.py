"""HTML report: sensorTestReport.html in the run's folder, light enough to mail with its folder.

Plots (matplotlib, Agg) and camera stills are inside the page as PNG/JPEG data: URIs; videos
and WAV files are played from relative links to the files next to the report, except short
clips within the embedding budget (files.py: at most 512 kB a file, 1 MB in all). Nothing is
loaded from the network, so the page opens offline.

Layout of this package (docs/results.md, "sensorTestReport.html"):
  page.py        run results -> the template's context -> HTML
  templates/     report.html.j2 (Jinja2, autoescaping on) and report.css
  blocks.py      what a view returns (headings, tables, images, players), rendered by the template
  values.py      one typed values dataclass per sensor family; adapters.py builds them from the
                 checks' dicts (every dict key the report reads is there)
  views/         one small renderer per sensor family
  plots.py       every matplotlib figure
  files.py       stills, media, the size budget

`HtmlReport` is the runner observer: it writes the report on run_ended (also for an interrupted
run) and never fails the run; a report error is printed as one warning line.
"""
import os
import sys
import threading
import time
from typing import TYPE_CHECKING, Optional, TextIO

from ...observer import RunObserver
from ...results import REPORT_FILE, RunResult
from ..atomicfile import write_atomic
from ..terminal import fill
from .files import MAX_EMBED_BYTES

if TYPE_CHECKING:
    from ...plan.settings import TestPlan



class HtmlReport(RunObserver):
    """Runner observer: writes sensorTestReport.html into `folder` when the run ends."""

    def __init__(self, folder: Optional[str], out: Optional[TextIO] = None, max_embed: int = MAX_EMBED_BYTES) -> None:
        self.folder = folder
        self.out = out
        self.max_embed = max_embed

    def run_started(self, run: RunResult, plan: 'TestPlan') -> None:
        # import matplotlib and Jinja2 now, in the background, so that writing the report at
        # the end (also after Ctrl-C) does not wait for them
        threading.Thread(target=_warm_up, daemon=True, name='report-warm-up').start()

    def run_ended(self, run: RunResult) -> None:
        stream = self.out or sys.stdout
        t0 = time.monotonic()
        try:
            path = write_report(run, self.folder, max_embed=self.max_embed)
            size = os.path.getsize(path)
            stream.write(fill('report: %s (%s, %.1f s)' % (
                path, '%.1f MB' % (size / 1e6) if size >= 1e6 else '%d kB' % round(size / 1e3),
                time.monotonic() - t0)) + '\n')
        except (Exception, KeyboardInterrupt) as e:   # the report never fails the run
            text = str(e).strip().splitlines()[0] if str(e).strip() else ''
            stream.write('sensorTest: warning: HTML report not written: %s%s\n'
                         % (type(e).__name__, (': ' + text) if text else ''))
        stream.flush()


def _warm_up() -> None:
    try:
        import jinja2  # noqa: F401
        from matplotlib.backends import backend_agg  # noqa: F401
        from matplotlib.figure import Figure  # noqa: F401
    except Exception:  # the report says what went wrong when it is written
        pass


def render(run: RunResult, folder: Optional[str] = None, max_embed: int = MAX_EMBED_BYTES) -> str:
    """The report of `run` as one HTML string; recordings are read from `folder`."""
    from .page import render as render_page
    return render_page(run, folder or run.output_dir or '.', max_embed)


def write_report(run: RunResult, folder: Optional[str] = None, max_embed: int = MAX_EMBED_BYTES) -> str:
    """Render `run` and write <folder>/sensorTestReport.html (folder: the run's output_dir).
    Returns the path."""
    folder = folder or run.output_dir or '.'
    path = os.path.join(folder, REPORT_FILE)
    text = render(run, folder, max_embed)
    write_atomic(path, text)   # a whole file or none, with the user's umask (meant to be shared)
    return path
