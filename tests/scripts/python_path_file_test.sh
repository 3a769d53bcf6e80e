#!/usr/bin/env bash
# scripts/python-path-file.sh in a throw-away HOME: it writes the path file where there is none,
# leaves one naming another build's module alone (with a note), and replaces one naming a folder
# without the module. Exit 77 (skipped) where /usr/bin/python3 has no user site.
set -euo pipefail
script="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/scripts/python-path-file.sh"
home="$(mktemp -d)"
trap 'rm -rf "$home"' EXIT
export HOME="$home" PYTHONUSERBASE="$home/.local"
[[ "$(/usr/bin/python3 -c 'import site; print(site.ENABLE_USER_SITE)')" == "True" ]] || exit 77
pth="$(/usr/bin/python3 -m site --user-site)/hemicontact.pth"
fail() { echo "FAIL: $*" >&2; exit 1; }
mkdir -p "$home/this/hemicontact" "$home/other/hemicontact"
touch "$home/this/hemicontact/__init__.py" "$home/other/hemicontact/__init__.py"

bash "$script" "$home/this" 2>/dev/null
[[ "$(cat "$pth")" == "$home/this" ]] || fail "no path file written: $(cat "$pth" 2>&1)"

echo "$home/other" >"$pth"
note="$(bash "$script" "$home/this" 2>&1)"
[[ "$(cat "$pth")" == "$home/other" ]] || fail "another build's path file was replaced"
[[ "$note" == *"left as it is"*"echo $home/this > $pth"* ]] || fail "no note on how to switch: $note"

rm -rf "$home/other"
bash "$script" "$home/this" 2>/dev/null
[[ "$(cat "$pth")" == "$home/this" ]] || fail "a path file naming a removed build was kept"
echo "python-path-file: 3 cases passed"
