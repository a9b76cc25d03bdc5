#!/bin/sh
# An engine that never answers: the runner must kill it (and its child).
# The optional argument, a fraction of a second added to the sleep, marks the
# sleeper so that a test can find its own among other test runs' processes.
sleep 1000 "${1:-0}"
