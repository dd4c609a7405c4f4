"""Unit: CHANGELOG.rst is read by catkin's own changelog parser (catkin_pkg.changelog, the one
`catkin_generate_changelog` and bloom use): it names this package, its newest section is the
version in package.xml with a date, and every section has bullet lines."""
import os
import xml.etree.ElementTree as ET

import pytest
from catkin_pkg.changelog import BulletList, get_changelog_from_path

# docutils' traverse() as catkin_pkg calls it warns on Debian 12's docutils; nothing to fix here
pytestmark = pytest.mark.filterwarnings('ignore::PendingDeprecationWarning')

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # test/docs/ -> the repository


def test_the_changelog_is_catkins_format_and_starts_at_the_packages_version():
    version = ET.parse(os.path.join(ROOT, 'package.xml')).getroot().findtext('version')
    changelog = get_changelog_from_path(os.path.join(ROOT, 'CHANGELOG.rst'), 'pepper_interface_tests')
    assert changelog is not None and changelog.package_name == 'pepper_interface_tests'
    sections = list(changelog.foreach_version())
    assert sections, 'no "X.Y.Z (YYYY-MM-DD)" section'
    assert sections[0][0] == version, 'the newest section must be package.xml\'s version %s' % version
    for v, date, content in sections:
        assert date is not None, v
        assert any(isinstance(part, BulletList) and part.bullets for part in content), '%s has no bullet' % v
