#!/bin/sh
# Man pages and bash completion: every page the build made renders with man -l without a
# warning, has its sections, and names every long option of its tool's --help (each
# command's for c4g-replay and c4g-ident); the completion script offers each tool's options,
# c4g-replay's and c4g-ident's commands, files for FILE options and cell-cli's words.
set -u
build=$1
bin=$build/bin
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
pass() { echo "PASS: $*"; }
bad() { echo "FAIL: $*"; fail=1; }
export LC_ALL=C MANWIDTH=100

# page TOOL-or-PAGE: the rendered text in $tmp/page.txt, warnings in $tmp/page.err
render() {
  man -l "$build/man/$1" >"$tmp/page.txt" 2>"$tmp/page.err"
}
for page in c4g-server.1 c4g-sim.1 c4g-replay.1 c4g-ident.1 cell-cli.1 cell-sim.1 c4gopen.3; do
  if [ ! -s "$build/man/$page" ]; then bad "$page was not built"; continue; fi
  render "$page"; rc=$?
  if [ "$rc" -eq 0 ] && [ ! -s "$tmp/page.err" ] && grep -q "^NAME" "$tmp/page.txt" && grep -q "^SEE ALSO" "$tmp/page.txt"; then
    pass "$page renders ($(wc -l <"$tmp/page.txt") lines, no warnings)"
  else
    bad "$page: man -l exit $rc: $(head -3 "$tmp/page.err")"
  fi
done
for page in c4g-server.1 c4g-sim.1 c4g-replay.1 c4g-ident.1 cell-cli.1 cell-sim.1; do
  grep -q "^EXIT STATUS" "$build/man/$page" 2>/dev/null || { man -l "$build/man/$page" 2>/dev/null | grep -q "^EXIT STATUS"; } \
    && pass "$page has EXIT STATUS" || bad "$page: no EXIT STATUS"
done

# every long option of --help in the page
options_of() { "$@" --help | sed -n 's/^  *\(-[A-Za-z0-9], \)\{0,1\}\(--[a-z0-9-]*\).*/\2/p' | sort -u; }
cover() { # PAGE TOOL [COMMAND]
  page=$1; shift
  render "$page"
  missing=''; n=0
  for o in $(options_of "$bin/$1" ${2:+"$2"}); do
    n=$((n + 1))
    grep -q -e "$o\b" "$tmp/page.txt" || missing="$missing $o"
  done
  [ "$n" -gt 2 ] && [ -z "$missing" ] && pass "$page names all $n options of $* --help" || bad "$page: $n options, missing:$missing"
}
for t in c4g-server c4g-sim cell-cli cell-sim; do cover "$t.1" "$t"; done
for c in summary check export rerun live plot; do cover c4g-replay.1 c4g-replay "$c"; done
for c in fit excite; do cover c4g-ident.1 c4g-ident "$c"; done
render c4gopen.3
grep -q "c4g_loop_rx" "$tmp/page.txt" && grep -q "pkg-config" "$tmp/page.txt" && pass "c4gopen(3) has the loop and the linking" || bad "c4gopen(3) content"

# bash completion
cat >"$tmp/c.bash" <<'SH'
. scripts/completion/c4gopen.bash
t() { COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); _c4gopen; echo "${COMPREPLY[*]}"; }
SH
comp() { # WANT WORDS...: the completions of the last word
  want=$1; shift
  got=$(PATH="$bin:$PATH" bash -c ". $tmp/c.bash; t \"\$@\"" t "$@")
  [ "$got" = "$want" ] && pass "complete '$*' -> $got" || bad "complete '$*' -> '$got', want '$want'"
}
comp "--json" c4g-server --js
comp "--moni --moni-type" c4g-server --mon
comp "--json" c4g-sim --js
comp "--csv" c4g-sim --cs
comp "summary" c4g-replay su
comp "--allow" c4g-replay check --al
comp "--plot" c4g-ident fit --pl
comp "fit" c4g-ident f
comp "--workspace" cell-sim --works
comp "--no-raw --no-history --no-hints" cell-cli --no-
comp "robot" cell-cli rob
comp "abs rel" cell-cli robot mov ""
comp "fixtures/server/traj_example.csv" c4g-server --traj fixtures/server/traj_ex
comp "" c4g-server --port ""
bash -n scripts/completion/c4gopen.bash && pass "completion script parses" || bad "bash -n"
exit $fail
