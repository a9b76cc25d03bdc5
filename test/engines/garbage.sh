#!/bin/sh
# An engine whose answer is not JSON.
cat > /dev/null
echo "this is not json {"
