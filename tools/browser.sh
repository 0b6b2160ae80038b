#!/bin/sh
# Headless Chromium and its WebDriver for the browser test of the 3-D view
# (tests/test_view.py), from the distribution's packages (Debian/Ubuntu: apt-get; needs
# root). Idempotent: installs only what is missing. Selenium itself is a Python test
# dependency (pip), not installed here.
set -eu
have() { command -v "$1" >/dev/null 2>&1; }
if have chromium && have chromedriver; then
    echo "browser.sh: chromium and chromedriver present: $(chromium --version 2>/dev/null | head -n 1)"
    exit 0
fi
if ! have apt-get; then
    echo "browser.sh: no apt-get here; install chromium and chromedriver another way" >&2
    exit 1
fi
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends \
    chromium chromium-driver
have chromium && have chromedriver
echo "browser.sh: installed $(chromium --version 2>/dev/null | head -n 1)"
