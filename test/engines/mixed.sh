#!/bin/sh
# An engine whose results cover every kind for the fixture corpus: the
# answer int-add-saturates expects (pass; real-sum and named-vars fail on
# it), unsupported for div-zero, a crash (engine-error) for three-calls.
req=$(cat)
case "$req" in
  *'"case":"mastertool-xe/calls/div-zero"'*) echo '{"verdict": "unsupported", "reason": "no division here"}' ;;
  *'"case":"mastertool-xe/calls/three-calls"'*) echo "crashed" >&2; exit 3 ;;
  *) echo '{"verdict": "ok", "operands": {"%M0012": 32767, "%M13.0": true}, "outputs": {"OUTPUT1": true}, "error": null}' ;;
esac
