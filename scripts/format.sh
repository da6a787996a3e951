#!/usr/bin/env bash
# Format and lint check of the whole tree (run by scripts/test.sh):
#   - clang-format (.clang-format; lammps_plugin/.clang-format for the
#     plugin's C++) on every tracked C/C++ file;
#   - ruff (settings in pyproject.toml) on every tracked Python file.
# With --fix, rewrites the files instead (clang-format -i, ruff --fix).
# The tools come from .venv (scripts/setup.sh installs pinned versions, so
# every machine formats alike).
set -euo pipefail
cd "$(dirname "$0")/.."

bin=.venv/bin
for tool in clang-format ruff; do
    [ -x "$bin/$tool" ] || { echo "format: $bin/$tool missing (run scripts/setup.sh)" >&2; exit 1; }
done

mapfile -t c_files < <(git ls-files '*.c' '*.h' '*.cpp')
mapfile -t py_files < <(git ls-files '*.py')

if [ "${1:-}" = "--fix" ]; then
    "$bin/clang-format" -i "${c_files[@]}"
    "$bin/ruff" check --fix --quiet "${py_files[@]}"
    exit 0
fi

status=0
echo "format: clang-format on ${#c_files[@]} C/C++ files"
"$bin/clang-format" --dry-run --Werror "${c_files[@]}" || status=1
echo "format: ruff on ${#py_files[@]} Python files"
"$bin/ruff" check --quiet "${py_files[@]}" || status=1
if [ $status -ne 0 ]; then
    echo "format: run 'bash scripts/format.sh --fix' (and fix what ruff cannot)" >&2
fi
exit $status
