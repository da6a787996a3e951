#!/usr/bin/env bash
# The size of the user docs and the shape of their headings.
#
#   bash scripts/doc_size.sh [DOCS_DIR]      (default: docs/ of this checkout)
#
# Prints the line count of every docs/**/*.md together, and the largest file
# with its count.  Exits non-zero when the total is 5000 lines or more, or
# when a Markdown heading (a line starting with '#' outside fenced code)
# holds a date (YYYY-MM-DD), a time of day (HH:MM) or the word "issue";
# each offending heading is printed as FILE:LINE: TEXT.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
docs="${1:-$root/docs}"
limit=5000

if [[ ! -d "$docs" ]]; then
    echo "doc_size: no directory $docs" >&2
    exit 2
fi

mapfile -d '' files < <(find "$docs" -type f -name '*.md' -print0 | sort -z)
if (( ${#files[@]} == 0 )); then
    echo "doc_size: no Markdown files under $docs" >&2
    exit 2
fi

total=0
largest=""
largest_lines=-1
for f in "${files[@]}"; do
    n=$(wc -l < "$f")
    total=$((total + n))
    if (( n > largest_lines )); then
        largest_lines=$n
        largest=$f
    fi
done

echo "docs: ${total} lines in ${#files[@]} Markdown files (limit: under ${limit})"
echo "largest: ${largest#"$root"/} (${largest_lines} lines)"

status=0
if (( total >= limit )); then
    echo "doc_size: ${total} lines is not under ${limit}" >&2
    status=1
fi

# Headings outside fenced code blocks (``` or ~~~).
bad=$(awk '
    FNR == 1 { fence = 0 }
    /^[ \t]*(```|~~~)/ { fence = !fence; next }
    fence { next }
    /^#/ {
        line = $0
        if (line ~ /[0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]/ ||
            line ~ /(^|[^0-9])([01]?[0-9]|2[0-3]):[0-5][0-9]([^0-9]|$)/ ||
            tolower(line) ~ /(^|[^a-z])issues?([^a-z]|$)/)
            printf "%s:%d: %s\n", FILENAME, FNR, line
    }' "${files[@]}")
if [[ -n "$bad" ]]; then
    echo "doc_size: headings with a date, a time of day or \"issue\":" >&2
    echo "${bad//"$root"\//}" >&2
    status=1
fi
exit "$status"
