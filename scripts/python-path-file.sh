#!/usr/bin/env bash
# Usage: scripts/python-path-file.sh MODULE_DIR
# Makes Debian's /usr/bin/python3 import hemicontact from MODULE_DIR (a build's python/ folder):
# a hemicontact.pth in the user's site-packages naming it. A path file rather than a copy
# (cmake --install --component python installs a copy, for packaging): no root needed, and a
# rebuild is what python3 imports next, with no second copy to go stale. Nothing where python3
# has no user site. Another checkout's build (a clean-clone CI run, a second worktree) does not
# take over the user's import: a path file naming another build's module that still exists is
# left alone, with a note saying how to switch; one naming a folder without the module is replaced.
set -euo pipefail
module_dir="$1"
python=/usr/bin/python3
site="$("$python" -m site --user-site 2>/dev/null)" || exit 0
[[ "$("$python" -c 'import site; print(site.ENABLE_USER_SITE)')" == "True" ]] || exit 0
pth="$site/hemicontact.pth"
other="$(head -n 1 "$pth" 2>/dev/null || true)"
if [[ -n "$other" && "$other" != "$module_dir" && -f "$other/hemicontact/__init__.py" ]]; then
  echo "build: python3 imports hemicontact from $other ($pth, another build's), left as it is;" \
       "to import this build's module: echo $module_dir > $pth" >&2
  exit 0
fi
mkdir -p "$site"
echo "$module_dir" >"$pth"
echo "build: python3 imports hemicontact from $module_dir ($pth)" >&2
