#!/usr/bin/env bash
# The main job's report.html in a real browser: Debian's headless Chromium loads it at 1400×900
# and a script injected into a copy of the page checks that no console error or failed load
# happened, that every image loaded, that the verdict fits the first screen, and that no table is
# wider than the page outside its own scroll box. Run by .ci/run after scripts/test.sh (it is not
# part of the test command's time budget); first it checks the checker on a page built to fail.
#
#   scripts/report_check.sh [REPORT_HTML] [--screenshots DIR]
#
# REPORT_HTML defaults to out/quick/report.html, made by scripts/main.sh when missing. With
# --screenshots, also writes DIR/report-first-screen.png (1400×900) and DIR/report-charts.png.
# Installs Debian's `chromium` with apt-get (sudo when not root) where it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

report=out/quick/report.html
shots=
while [ $# -gt 0 ]; do
  case "$1" in
    --screenshots) shots=$2; shift 2 ;;
    *) report=$1; shift ;;
  esac
done

if ! command -v chromium >/dev/null; then
  sudo=; [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi
if [ ! -f "$report" ] && [ "$report" = out/quick/report.html ]; then
  bash scripts/main.sh >/dev/null
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Chromium as the machine's notes run it headless: no sandbox (root), no GPU, and none of the
# background connections a closed network refuses.
# `browser WIDTH,HEIGHT ARGS…`.
browser() {
  local size=$1; shift
  timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$work/profile" --window-size="$size" --hide-scrollbars "$@" 2>"$work/stderr"
}

# Hooks first in <head>, so that an error anywhere on the page is caught; the checks run on load.
read -r -d '' hook <<'JS' || true
<script>
window.__errors = [];
(function () {
  var e = console.error;
  console.error = function () { window.__errors.push('console.error: ' + Array.from(arguments).join(' ')); e.apply(console, arguments); };
  window.addEventListener('error', function (ev) {
    var t = ev.target;
    window.__errors.push(t && t !== window ? 'failed to load <' + t.tagName.toLowerCase() + '> ' + (t.src || t.href || '').slice(0, 80) : 'error: ' + ev.message);
  }, true);
  window.addEventListener('unhandledrejection', function (ev) { window.__errors.push('unhandled rejection: ' + ev.reason); });
})();
</script>
JS
read -r -d '' checks <<'JS' || true
<script>
window.addEventListener('load', function () {
  var fails = [], width = document.documentElement.clientWidth;
  fails = fails.concat(window.__errors);
  var imgs = Array.from(document.images);
  imgs.forEach(function (i) { if (!i.complete || i.naturalWidth === 0) fails.push('image did not load: ' + (i.alt || i.src.slice(0, 60))); });
  var v = document.getElementById('verdict');
  if (!v) { fails.push('no verdict (#verdict)'); }
  else {
    var r = v.getBoundingClientRect();
    if (r.top < 0 || r.bottom > 900) fails.push('verdict not within the first 1400x900 screen: top ' + r.top + ', bottom ' + r.bottom);
  }
  Array.from(document.querySelectorAll('table')).forEach(function (t, k) {
    var box = t.parentElement && getComputedStyle(t.parentElement).overflowX;
    var scrolls = box === 'auto' || box === 'scroll';
    var right = (scrolls ? t.parentElement : t).getBoundingClientRect().right;
    if (right > width + 0.5) fails.push('table ' + k + ' reaches ' + right + ' px on a ' + width + ' px page' + (scrolls ? ' (its box too)' : ' outside any scroll box'));
  });
  if (document.documentElement.scrollWidth > width) fails.push('the page scrolls sideways: ' + document.documentElement.scrollWidth + ' px wide');
  var out = document.createElement('pre');
  out.id = 'wavetrace-check';
  out.textContent = JSON.stringify({images: imgs.length, tables: document.querySelectorAll('table').length, fails: fails});
  document.body.appendChild(out);
});
</script>
JS

# Checks `$1` (an HTML file); prints the result, and returns 1 when a check failed.
check() {
  local page="$work/checked.html"
  python3 - "$1" "$page" "$hook" "$checks" <<'PY'
import sys
src, dst, hook, checks = sys.argv[1:5]
html = open(src, encoding="utf-8").read()
i = html.find("<head>")
html = html[: i + 6] + hook + html[i + 6 :] if i >= 0 else hook + html
j = html.rfind("</body>")
html = html[:j] + checks + html[j:] if j >= 0 else html + checks
open(dst, "w", encoding="utf-8").write(html)
PY
  # Beside the report, so that relative links resolve as they do for the original.
  cp "$page" "$(dirname "$1")/.report-check.html"
  browser 1400,900 --virtual-time-budget=10000 --dump-dom "file://$(realpath "$(dirname "$1")")/.report-check.html" >"$work/dom.html" || true
  rm -f "$(dirname "$1")/.report-check.html"
  python3 - "$work/dom.html" "$1" <<'PY'
import html, json, re, sys
dom = open(sys.argv[1], encoding="utf-8").read()
m = re.search(r'<pre id="wavetrace-check">(.*?)</pre>', dom, re.S)
if not m:
    print(f"report check: {sys.argv[2]}: the checks did not run (the page did not load?)")
    sys.exit(1)
r = json.loads(html.unescape(m.group(1)))
for f in r["fails"]:
    print(f"report check: {sys.argv[2]}: {f}")
print(f"report check: {sys.argv[2]}: {r['images']} images, {r['tables']} tables, {len(r['fails'])} failed checks")
sys.exit(1 if r["fails"] else 0)
PY
}

# The checker itself: a page with a broken image, a console error, a wide table outside any
# scroll box and no verdict must fail every one of those checks.
bad="$work/bad/report.html"
mkdir -p "$work/bad"
cat >"$bad" <<'HTML'
<!DOCTYPE html><html><head><meta charset="utf-8"></head><body><img src="missing.png" alt="missing">
<table><tr><td style="min-width:3000px">wide</td></tr></table><img src="data:image/png;base64,AAAA" alt="corrupt">
<script>console.error("boom")</script></body></html>
HTML
if out=$(check "$bad"); then
  echo "report check: the checker passed a page built to fail:"; echo "$out"; exit 1
fi
for want in "failed to load <img>" "image did not load: missing" "image did not load: corrupt" "console.error: boom" \
  "no verdict" "outside any scroll box"; do
  if ! grep -qF "$want" <<<"$out"; then
    echo "report check: the checker missed \"$want\" on a page built to fail:"; echo "$out"; exit 1
  fi
done

check "$report"

if [ -n "$shots" ]; then
  mkdir -p "$shots"
  url="file://$(realpath "$report")"
  browser 1400,900 --screenshot="$shots/report-first-screen.png" "$url" >/dev/null
  # The charts: the page from its top at a taller window, cropped below by the window.
  browser 1400,2000 --screenshot="$shots/report-charts.png" "$url" >/dev/null
  echo "screenshots in $shots"
fi
