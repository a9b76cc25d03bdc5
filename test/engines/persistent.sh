#!/bin/sh
# A persistent engine (one request a line, one answer a line) for the
# fixture corpus: the answer int-add-saturates expects to every request,
# except a crash (exit 3) on div-zero and a hang on three-calls. Each start
# of the process adds a line to the file named by $1, if given.
[ -n "$1" ] && echo started >> "$1"
while IFS= read -r line; do
  case "$line" in
    *'"case":"mastertool-xe/calls/div-zero"'*) echo "crashed on div-zero" >&2; exit 3 ;;
    *'"case":"mastertool-xe/calls/three-calls"'*) sleep 60 ;;
    *) echo '{"verdict": "ok", "operands": {"%M0012": 32767, "%M13.0": true}, "outputs": {"OUTPUT1": true}, "error": null}' ;;
  esac
done
