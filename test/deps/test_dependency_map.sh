#!/usr/bin/env bash
# ctest deps_map: the dependency map (package.xml's keys and the rosdep rules
# of rosdep/ and test/data/rosdep_upstream.yaml) holds for this tree, and the
# check fails, naming the file and the package, on a launch file that names an
# unmapped package and on a package.xml key no rule maps.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
check=(/usr/bin/python3 "$root/test/deps/check_dependency_map.py")
status=0
bad() { echo "FAIL: $*"; status=1; }

echo "== this tree"
"${check[@]}" "$root" || bad "the dependency map does not hold for this tree"

tmp=$(mktemp -d /tmp/af_deps.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
copy_tree() {
  rm -rf "$tmp/tree" && mkdir -p "$tmp/tree/scripts" "$tmp/tree/test/data"
  cp -r "$root/launch" "$root/package.xml" "$root/rosdep" "$tmp/tree/"
  cp "$root/test/data/rosdep_upstream.yaml" "$tmp/tree/test/data/"
}

echo "== a launch file naming an unmapped package (must fail)"
copy_tree
cat >"$tmp/tree/launch/mic.launch" <<'XML'
<launch>
  <node pkg="audio_capture" type="audio_capture" name="mic"/>
</launch>
XML
out=$("${check[@]}" "$tmp/tree") && bad "a launch file naming audio_capture passed the check"
echo "$out"
grep -q "launch/mic.launch: names package 'audio_capture', which package.xml does not list" <<<"$out" ||
  bad "no line names launch/mic.launch and audio_capture as unlisted"
grep -q "launch/mic.launch: package 'audio_capture' has no rosdep rule" <<<"$out" ||
  bad "no line names audio_capture as unmapped"

echo "== package.xml naming a key the map lacks (must fail)"
copy_tree
sed -i 's|<depend>libgsl</depend>|<depend>libgsl</depend><depend>libsndfile</depend>|' "$tmp/tree/package.xml"
out=$("${check[@]}" "$tmp/tree") && bad "package.xml naming libsndfile passed the check"
echo "$out"
grep -q "package.xml: package 'libsndfile' has no rosdep rule" <<<"$out" || bad "no line names libsndfile"
echo "== setup.sh refuses the unmapped key before installing anything"
mkdir -p "$tmp/tree/scripts" && cp "$root/scripts/setup.sh" "$tmp/tree/scripts/"
out=$(bash "$tmp/tree/scripts/setup.sh" 2>&1) && bad "setup.sh accepted an unmapped key"
echo "$out"
grep -q "package.xml names 'libsndfile'" <<<"$out" || bad "setup.sh did not name libsndfile"

echo "== a rule whose first package does not ship the package.xml (must fail)"
copy_tree
sed -i 's|bookworm: \[libroscpp-dev, |bookworm: [ros-core-dev, libroscpp-dev, |' \
  "$tmp/tree/rosdep/debian_ros.yaml"
out=$("${check[@]}" "$tmp/tree") && bad "a wrong first package for roscpp passed the check"
echo "$out"
grep -q "'roscpp' maps first to 'ros-core-dev', but /usr/share/roscpp/package.xml is shipped by 'libroscpp-dev'" <<<"$out" ||
  bad "no line names the package that ships roscpp's package.xml"

[ "$status" -eq 0 ] && echo "deps_map: pass"
exit "$status"
