#!/usr/bin/env bash
# Make sure headless Chromium is there for scripts/docs/check_site.py: Debian's package `chromium`,
# installed non-interactively when absent, only as root with apt-get; otherwise fail saying how.
set -euo pipefail
if [ -n "${CHROMIUM:-}" ] || command -v chromium >/dev/null 2>&1; then
  exit 0
fi
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq chromium >/dev/null
  command -v chromium >/dev/null
else
  echo "chromium is not installed: the documentation check opens the site in headless Chromium." >&2
  echo "Install Debian's package as root (apt-get install chromium), or set CHROMIUM to a Chromium binary." >&2
  exit 1
fi
