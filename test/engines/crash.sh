#!/bin/sh
# An engine that exits with status 3 without answering.
cat > /dev/null
echo "engine broke" >&2
exit 3
