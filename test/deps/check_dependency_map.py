#!/usr/bin/env python3
"""The one dependency list, checked: every package that package.xml, a launch
file or a .test file names is a key of scripts/debian_packages.yaml, and on
this machine the map's first package for a ROS package is the one that ships
its package.xml (dpkg -S). Launch and test files may only name packages that
package.xml lists, since setup.sh installs from package.xml.

Usage: check_dependency_map.py ROOT   (exit 0 clean, 1 with one line a finding)
"""
import glob
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

SELF = "acoustic_firmness"


def read_map(path):
    """`key: [a, b]` a line; comments and blank lines skipped."""
    out = {}
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        m = re.fullmatch(r"([A-Za-z0-9_.+-]+):\s*\[([^\]]*)\]", line)
        if not m:
            sys.exit(f"{path}:{n}: not `key: [packages]`: {line!r}")
        pkgs = [p.strip() for p in m.group(2).split(",") if p.strip()]
        if not pkgs or m.group(1) in out:
            sys.exit(f"{path}:{n}: key {m.group(1)!r} empty or mapped twice")
        out[m.group(1)] = pkgs
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
    mapping = read_map(os.path.join(root, "scripts", "debian_packages.yaml"))
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
        if key not in mapping:
            findings.append(f"{where}: package '{key}' is not a key of "
                            "scripts/debian_packages.yaml (no Debian package installs it)")
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
