"""Unit: the README's "Speed" section is for users (issue 45): what `make bench` measures, its
goals and the measured ratios in one table; the profiles (where the time went) live in
docs/benchmark.md, whose "Where the time went" section holds them."""
import os
import re
from typing import List

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # test/docs/ -> the repository


def section(path: str, heading: str) -> str:
    """The text under `## heading` up to the next heading of level 2 or above."""
    with open(path, encoding='utf-8') as f:
        text = f.read()
    m = re.search(r'^## %s\n(.*?)(?=^#{1,2} |\Z)' % re.escape(heading), text, flags=re.M | re.S)
    assert m, '%s has no "## %s" section' % (path, heading)
    return m.group(1)


def tables(text: str) -> List[List[str]]:
    """Each Markdown table of `text` as its lines."""
    out: List[List[str]] = []
    previous = False
    for line in text.splitlines():
        row = line.startswith('|')
        if row and not previous:
            out.append([])
        if row:
            out[-1].append(line)
        previous = row
    return out


def test_the_readmes_speed_section_has_one_table_of_goals_and_ratios():
    speed = section(os.path.join(ROOT, 'README.md'), 'Speed')
    found = tables(speed)
    assert len(found) == 1, ('README.md "Speed" has %d tables; keep one (job, goal, measured) and move '
                             'the profiles to docs/benchmark.md: %s' % (len(found), [t[0] for t in found]))
    assert [c.strip() for c in found[0][0].strip('|').split('|')] == ['job', 'goal', 'measured']
    assert 'py-spy' not in speed, 'profiles belong in docs/benchmark.md'


def test_the_profiles_are_in_the_benchmark_page():
    where = section(os.path.join(ROOT, 'docs', 'benchmark.md'), 'Where the time went')
    headers = [t[0] for t in tables(where)]
    assert any(h.startswith('| profile | before | after |') for h in headers), headers
