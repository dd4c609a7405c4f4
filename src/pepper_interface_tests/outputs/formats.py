"""The output formats of a run: one table (file name, what it is, renderer, option) from which
the results files written at the end, the terminal's "results in" line and the report's links
to the other files are derived.

Order matters and is the table's: the .dat is written block by block as sensors finish (its
renderer is None here: outputs/observers.ResultFiles streams it), then JUnit, then the JSON,
so that the JSON's `exit_code` and `write_errors` already know whether JUnit could be written;
the HTML report comes last (outputs/report, an observer of its own: it reads the others' files).
"""
from dataclasses import dataclass
from typing import Callable, Optional, Tuple

from .. import results
from ..plan.options import Options
from . import files

Renderer = Callable[[results.RunResult, str], None]


@dataclass(frozen=True)
class OutputFormat:
    file: str                       # its name in the run folder
    what: str                       # in words
    render: Optional[Renderer]      # writes the whole file at the end of the run; None: see above
    option: Optional[str] = None    # the Options switch that leaves it out (--no-report), or None

    def enabled(self, options: Options) -> bool:
        return self.option is None or getattr(options, self.option) is not False


FORMATS: Tuple[OutputFormat, ...] = (
    OutputFormat(results.OUTPUT_FILE, "the specification's output file", None),
    OutputFormat(results.JUNIT_FILE, 'JUnit XML', files.write_junit),
    OutputFormat(results.JSON_FILE, 'JSON', files.write_json),
    OutputFormat(results.REPORT_FILE, 'HTML report', None, 'report'),
)


def written_at_end() -> Tuple[OutputFormat, ...]:
    """The formats the results files observer renders whole when the run ends, in order."""
    return tuple(f for f in FORMATS if f.render is not None)


def results_files() -> Tuple[str, ...]:
    """The files every run writes (the "results in" line; the report links to them)."""
    return tuple(f.file for f in FORMATS if f.option is None)
