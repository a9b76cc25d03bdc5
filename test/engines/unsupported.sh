#!/bin/sh
# An engine that implements nothing.
cat > /dev/null
echo '{"verdict": "unsupported", "reason": "no engine here"}'
