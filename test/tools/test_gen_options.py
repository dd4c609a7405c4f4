"""Unit: docs/options.md is what tools/gen_options.py writes from the options' one declaration
(plan/options.py OPTIONS) and sensorTest's argument parser: a page left stale after an option is
added, renamed or reworded fails here."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # test/tools/ -> the repository
sys.path.insert(0, os.path.join(ROOT, 'tools'))
import gen_options  # noqa: E402

from pepper_interface_tests.plan import options  # noqa: E402


def test_docs_options_md_is_generated_from_the_parser():
    with open(gen_options.PAGE, encoding='utf-8') as f:
        assert f.read() == gen_options.page(), 'docs/options.md is stale: run `make docs`'


def test_every_flag_and_param_is_on_the_page():
    text = gen_options.page()
    for o in options.OPTIONS:
        assert '`%s' % o.flag in text, o.flag
        assert ('`~%s`' % o.name in text) == (o.name in options.PARAMS), o.name


def test_a_stale_page_fails_the_check(tmp_path, monkeypatch, capsys):
    """The check the test above relies on: a page missing an option, or with an option's help
    changed in the code since, is stale (exit 1, the fix named)."""
    assert gen_options.main(['--check']) == 0
    page = tmp_path / 'options.md'
    monkeypatch.setattr(gen_options, 'PAGE', str(page))
    page.write_text(gen_options.page().replace('| `--quick` |', '| `--quick-gone` |'), encoding='utf-8')
    assert gen_options.main(['--check']) == 1
    assert 'make docs' in capsys.readouterr().err
    page.write_text(gen_options.page(), encoding='utf-8')
    assert gen_options.main(['--check']) == 0
    quick = next(o for o in options.OPTIONS if o.flag == '--quick')
    changed = tuple(o if o is not quick else o.__class__(**dict(o.__dict__, help='reworded'))
                    for o in options.OPTIONS)
    monkeypatch.setattr(options, 'OPTIONS', changed)
    assert gen_options.main(['--check']) == 1       # the code changed, the page did not
