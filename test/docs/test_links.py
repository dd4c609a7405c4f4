"""Unit: every relative link in README.md and docs/*.md resolves: the file exists, and a
`#anchor` names a heading of the page it points to (GitHub's anchors: lower case, punctuation
dropped, spaces as hyphens, a repeated heading suffixed -1, -2, ...). Links inside code are text,
not links. A page moved or a heading renamed without its links fails here."""
import os
import re
from typing import Dict, List, Set

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # test/docs/ -> the repository
LINK = re.compile(r'(?<!!)\[[^\]\n]*\]\(([^)\s]+)\)|!\[[^\]\n]*\]\(([^)\s]+)\)')
HEADING = re.compile(r'^#{1,6}\s+(.*?)\s*#*\s*$')


def pages() -> List[str]:
    docs = os.path.join(ROOT, 'docs')
    return [os.path.join(ROOT, 'README.md')] + sorted(
        os.path.join(docs, n) for n in os.listdir(docs) if n.endswith('.md'))


def prose(text: str) -> str:
    """The text without fenced code blocks and inline code spans (their brackets are not links)."""
    text = re.sub(r'^```.*?^```', lambda m: '\n' * m.group(0).count('\n'), text, flags=re.M | re.S)
    return re.sub(r'`[^`\n]*`', '', text)


def slug(heading: str) -> str:
    s = re.sub(r'\[([^\]]*)\]\([^)]*\)', r'\1', heading).strip().lower()
    s = re.sub(r'[^\w\- ]', '', s.replace('`', ''))
    return s.replace(' ', '-')


def anchors(path: str) -> Set[str]:
    seen: Dict[str, int] = {}
    out = set()
    with open(path, encoding='utf-8') as f:
        text = re.sub(r'^```.*?^```', '', f.read(), flags=re.M | re.S)
    for line in text.splitlines():
        m = HEADING.match(line)
        if m:
            base = slug(m.group(1))
            n = seen.get(base, 0)
            seen[base] = n + 1
            out.add(base if n == 0 else '%s-%d' % (base, n))
    out.update(re.findall(r'<a (?:name|id)="([^"]+)"', text))
    return out


def broken_links(path: str) -> List[str]:
    """'file:line: target: why' for each relative link of a markdown file that does not resolve."""
    with open(path, encoding='utf-8') as f:
        text = prose(f.read())
    out = []
    for m in LINK.finditer(text):
        target = m.group(1) or m.group(2)
        if re.match(r'[a-z][a-z0-9+.-]*:', target):       # http:, https:, mailto:
            continue
        where = '%s:%d: %s' % (os.path.relpath(path, ROOT), text.count('\n', 0, m.start()) + 1, target)
        file_part, _, anchor = target.partition('#')
        dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
        if not os.path.exists(dest):
            out.append(where + ': no such file')
        elif anchor and dest.endswith('.md') and anchor not in anchors(dest):
            out.append(where + ': no heading with this anchor in ' + os.path.relpath(dest, ROOT))
    return out


@pytest.mark.parametrize('page', pages(), ids=lambda p: os.path.relpath(p, ROOT))
def test_every_relative_link_resolves(page):
    assert broken_links(page) == []


def test_a_broken_link_or_anchor_is_named(tmp_path):
    (tmp_path / 'other.md').write_text('# Other page\n\n## Motion check (`--move`)\n\n## Motion check (`--move`)\n')
    page = tmp_path / 'page.md'
    page.write_text('# Page\n[ok](other.md) [ok](other.md#motion-check---move) [ok](other.md#motion-check---move-1)\n'
                    '[here](#page) [web](https://example.org/x.md) `[code](gone.md)`\n'
                    '```\n[in a block](gone.md)\n```\n'
                    '[gone](gone.md)\n[moved](other.md#motion)\n![img](pic.png)\n')
    assert broken_links(str(page)) == [
        '%s:7: gone.md: no such file' % os.path.relpath(str(page), ROOT),
        '%s:8: other.md#motion: no heading with this anchor in %s' % (
            os.path.relpath(str(page), ROOT), os.path.relpath(str(tmp_path / 'other.md'), ROOT)),
        '%s:9: pic.png: no such file' % os.path.relpath(str(page), ROOT)]
