#!/usr/bin/env python3
"""The one dependency list, checked: every package that package.xml, a launch
file or a .test file names is a rosdep key with a rule for Debian 12
(bookworm) in the rule files, read in rosdep's order (for each key, the first
file with a Debian rule wins): rosdep/acoustic_firmness.yaml,
rosdep/debian_ros.yaml, test/data/rosdep_upstream.yaml (the files
scripts/setup.sh installs from). On this machine the rule's first package for
a ROS package is the one that ships its package.xml (dpkg -S). Launch and test
files may only name packages that package.xml lists, since setup.sh installs
from package.xml.

Usage: check_dependency_map.py ROOT   (exit 0 clean, 1 with one line a finding)
"""
import glob
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import yaml

SELF = "acoustic_firmness"
RELEASE = "bookworm"
RULE_FILES = ("rosdep/acoustic_firmness.yaml", "rosdep/debian_ros.yaml",
              "test/data/rosdep_upstream.yaml")


def read_map(root):
    """{key: [Debian packages for RELEASE]}: per key, the first file with a
    `debian` rule wins (as in rosdep); in it, a list, or RELEASE's list, else
    '*''s. A key whose winning rule has none for RELEASE maps to []."""
    out = {}
    for rel in RULE_FILES:
        path = os.path.join(root, rel)
        data = yaml.safe_load(open(path, encoding="utf-8")) or {}
        for key, rule in data.items():
            if key in out or not isinstance(rule, dict) or "debian" not in rule:
                continue
            deb = rule["debian"]
            if isinstance(deb, dict):
                deb = deb.get(RELEASE, deb.get("*"))
            if deb is not None and not (isinstance(deb, list) and
                                        all(isinstance(p, str) for p in deb)):
                sys.exit(f"{rel}: the Debian rule of {key!r} is not a list of apt packages")
            out[key] = list(deb or [])
    return out


def package_xml_keys(path):
    root = ET.parse(path).getroot()
    return {e.text.strip() for e in root if e.tag.endswith("depend") and e.text}


def named_in(path):
    """Packages a launch or .test file names: pkg="X" and $(find X)."""
    text = open(path, encoding="utf-8").read()
    names = set(re.findall(r'\bpkg="([^"$]+)"', text))
    names |= set(re.findall(r"\$\(find\s+([^)\s]+)\)", text))
    return names - {SELF}


def owner(path):
    r = subprocess.run(["dpkg", "-S", path], capture_output=True, text=True)
    if r.returncode != 0:
        return None
    return r.stdout.split(":", 1)[0].strip()


def installed(pkg):
    r = subprocess.run(["dpkg-query", "-W", "-f=${Status}", pkg], capture_output=True, text=True)
    return r.returncode == 0 and "install ok installed" in r.stdout


def check(root):
    findings = []
    mapping = read_map(root)
    declared = package_xml_keys(os.path.join(root, "package.xml"))
    users = {k: "package.xml" for k in declared}
    files = sorted(glob.glob(os.path.join(root, "launch", "*.launch")) +
                   glob.glob(os.path.join(root, "test", "**", "*.test"), recursive=True))
    ros_named = set()
    for f in files:
        rel = os.path.relpath(f, root)
        for name in sorted(named_in(f)):
            ros_named.add(name)
            users.setdefault(name, rel)
            if name not in declared:
                findings.append(f"{rel}: names package '{name}', which package.xml does not "
                                "list (setup.sh installs from package.xml)")
    for key in sorted(users):
        where = users[key]
        if not mapping.get(key):
            findings.append(f"{where}: package '{key}' has no rosdep rule for Debian "
                            f"{RELEASE} in {', '.join(RULE_FILES)} (no Debian package installs it)")
            continue
        first = mapping[key][0]
        xml = f"/usr/share/{key}/package.xml"
        if os.path.exists(xml):
            ships = owner(xml)
            if ships != first:
                findings.append(f"{where}: '{key}' maps first to '{first}', but {xml} is "
                                f"shipped by '{ships}' (dpkg -S)")
        elif key in ros_named:
            findings.append(f"{where}: ROS package '{key}' has no {xml} on this machine")
        elif not installed(first):
            findings.append(f"{where}: '{key}' maps first to '{first}', which is not installed")
    return findings, len(users)


def main():
    findings, n = check(sys.argv[1] if len(sys.argv) > 1 else ".")
    for f in findings:
        print(f)
    print(f"deps_map: {n} packages checked, {len(findings)} findings")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
