#!/bin/sh
# An engine that prints without end.
yes "flooding the runner with output"
