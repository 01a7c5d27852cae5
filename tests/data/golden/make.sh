#!/usr/bin/env bash
# Stores the golden outputs: runs every line of commands.txt with the `metamoran` binary given as
# $1 and writes each named line's stdout beside this script. Run it once, at the commit before a
# restructuring that must not change behaviour; host-tools/tests/golden.rs then compares.
#   tests/data/golden/make.sh target/debug/metamoran
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/scenes" "$work/drives" "$work/tmp"
while IFS=$'\t' read -r name args; do
  case "$name" in ''|'#'*) continue ;; esac
  args=${args//\{scenes\}/$work/scenes}
  args=${args//\{drives\}/$work/drives}
  args=${args//\{tmp\}/$work/tmp}
  echo "golden: metamoran $args" >&2
  # shellcheck disable=SC2086
  if [ "$name" = "-" ]; then "$bin" $args >/dev/null; else "$bin" $args >"$here/$name"; fi
done <"$here/commands.txt"
