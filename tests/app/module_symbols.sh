#!/bin/sh
# Layout.ModulesFindTheirEngineSymbolsInFird: every engine symbol (fird::, and the engine's
# vtables and typeinfo) that an export module leaves undefined is one that the program
# exports (cmake/fird_module_exports.list), so that the module loads (RTLD_NOW) in every
# command that needs it. Reads the files with binutils' nm: the modules' undefined
# symbols against the program's dynamic, defined ones.
# Usage: module_symbols.sh PROGRAM MODULE...
set -eu
program=$1
shift
exported=$(mktemp)
trap 'rm -f "$exported"' EXIT
nm -D --defined-only "$program" | awk '{print $3}' | sort -u >"$exported"
status=0
for module in "$@"; do
  needed=$(nm -D --undefined-only "$module" | awk '{print $2}' | grep -E '^_Z(N|NK|TVN|TIN|TSN)4fird' | sort -u)
  [ -n "$needed" ] || { echo "$module: needs no engine symbol (is it a module of this build?)"; status=1; continue; }
  missing=$(printf '%s\n' "$needed" | comm -23 - "$exported")
  if [ -n "$missing" ]; then
    echo "$module: $(printf '%s\n' "$missing" | wc -l) engine symbols that $program does not export:"
    printf '%s\n' "$missing" | c++filt | sed 's/^/  /'
    status=1
  else
    echo "$module: $(printf '%s\n' "$needed" | wc -l) engine symbols, all exported by $program"
  fi
done
exit $status
