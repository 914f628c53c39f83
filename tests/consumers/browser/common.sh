# shellcheck shell=bash
# Sourced by the browser consumers' scripts (tests/consumers/*.sh).
#   need_browser            exit 77 (CTest's skip) with a message when node, chromium or the npm
#                           packages are missing
#   enter_work DIR          empty DIR and work in it
#   run_page OUT.json PAGE DATA_DIR [run-page.mjs options...]
#                           opens PAGE on DATA_DIR; its JSON report goes to OUT.json; returns
#                           run-page.mjs's status (0: the page finished without an error)
BROWSER_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

need_browser() {
  local missing=()
  command -v node >/dev/null || missing+=(node)
  [ -x "${CHROMIUM:-/usr/bin/chromium}" ] || missing+=(chromium)
  for p in three puppeteer-core 3d-tiles-renderer; do
    [ -f "$BROWSER_DIR/node_modules/$p/package.json" ] || missing+=("npm package $p")
  done
  if ((${#missing[@]})); then
    echo "skipped: ${missing[*]} not installed (./run installs them: chromium from Debian, the npm packages with npm ci in tests/consumers/browser)"
    exit 77
  fi
}

enter_work() {
  rm -rf "$1" && mkdir -p "$1" && cd "$1" || exit 1
}

run_page() {
  local out=$1
  shift
  node "$BROWSER_DIR/run-page.mjs" "$@" >"$out"
}
