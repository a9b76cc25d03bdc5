#!/bin/sh
# An engine that never answers: the runner must kill it (and its child).
sleep 1000
