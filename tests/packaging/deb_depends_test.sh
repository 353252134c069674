#!/usr/bin/env bash
# scripts/deb-depends must name the same packages as dpkg-shlibdeps (the Debian tool) for a native
# program: that is what lets its answer for a cross build, where dpkg-shlibdeps cannot run, be trusted.
# Usage: deb_depends_test.sh REPO_DIR PROGRAM
set -euo pipefail
repo=$1 program=$2
names() { tr ',' '\n' | sed 's/^ *//; s/ .*//; /^$/d' | sort -u; }

ours=$("$repo/scripts/deb-depends" / "$program")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/debian"
printf 'Source: slicecap\n\nPackage: slicecap\nArchitecture: any\n' >"$work/debian/control"
theirs=$(cd "$work" && dpkg-shlibdeps -O -e"$program" 2>/dev/null | sed -n 's/^shlibs:Depends=//p')

echo "deb-depends:    $ours"
echo "dpkg-shlibdeps: $theirs"
[[ -n $ours ]] || { echo "FAIL: deb-depends named no package"; exit 1; }
grep -q '^libc6$' <(names <<<"$ours") || { echo "FAIL: libc6 missing"; exit 1; }
if ! diff <(names <<<"$theirs") <(names <<<"$ours"); then
  echo "FAIL: the package names differ (< dpkg-shlibdeps, > deb-depends)"
  exit 1
fi
echo "PASS: same $(names <<<"$ours" | wc -l) packages"
