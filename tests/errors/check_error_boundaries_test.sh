#!/usr/bin/env bash
# scripts/check-error-boundaries on a small tree: it names a raw throw and a catch of
# std::invalid_argument with file:line and fails; it passes a re-throw, a module's own error and
# the allowed standard exceptions.
set -euo pipefail
check="$1/scripts/check-error-boundaries"
tree=$(mktemp -d)
trap 'rm -rf "$tree"' EXIT
mkdir -p "$tree/lib/m/src" "$tree/app"
cat > "$tree/lib/m/src/ok.cpp" <<'CPP'
// throw std::invalid_argument in a comment is not code
void f() {
  try { g(); } catch (const m::MError& e) { throw; }
  if (bad) throw m::MError("refused");
  if (early) throw std::logic_error("start before configure");
}
CPP
if ! "$check" --root "$tree" --quiet; then echo "a clean tree was refused"; exit 1; fi
cat > "$tree/app/bad.cpp" <<'CPP'
void h() {
  try { g(); } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
}
CPP
set +e
out=$("$check" --root "$tree")
status=$?
set -e
[ "$status" -eq 1 ] || { echo "exit $status, not 1:"; echo "$out"; exit 1; }
grep -q '^app/bad.cpp:2: ' <<<"$out" || { echo "the catch is not named:"; echo "$out"; exit 1; }
grep -q '^app/bad.cpp:3: ' <<<"$out" || { echo "the throw is not named:"; echo "$out"; exit 1; }
grep -q '2 left' <<<"$out" || { echo "not exactly 2 left:"; echo "$out"; exit 1; }
echo ok
