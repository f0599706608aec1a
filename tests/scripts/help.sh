#!/usr/bin/env bash
# Every script under scripts/ answers --help with its usage on stdout and exit status 0
# (issue 76: render.sh --help used to exit 2).
#   tests/scripts/help.sh ROOT
set -uo pipefail
root=${1:?the root of the repository}
status=0
while IFS= read -r script; do
    case $script in
    (*.py) output=$(python3 "$script" --help 2> /dev/null < /dev/null) ;;
    (*) output=$(bash "$script" --help 2> /dev/null < /dev/null) ;;
    esac
    code=$?
    if [ $code -ne 0 ] || [ -z "$output" ]; then
        echo "FAIL: $script --help exits $code and prints ${#output} characters"
        status=1
    else
        echo "ok: $script --help"
    fi
done < <(find "$root/scripts" -type f \( -name '*.sh' -o -name '*.py' \) | sort)
exit $status
