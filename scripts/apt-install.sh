#!/usr/bin/env bash
# Installs the Debian packages named as arguments when any of them is missing; used by setup.sh
# (scripts/packages.txt) and by the scripts that need more than the main build.
#   bash scripts/apt-install.sh clang libclang-rt-14-dev
set -euo pipefail
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "apt-install: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "$@" < /dev/null
fi
