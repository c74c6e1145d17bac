#!/bin/sh
# Install what symkin's LaTeX backend and its tests need, when it is missing:
# pdflatex with amsmath, amssymb, geometry (texlive-latex-base) and booktabs
# (texlive-latex-recommended), and
# pdftoppm (poppler-utils) for rendering pages to PNG.
# Idempotent: does nothing when both commands are present. Uses sudo only when not root.
set -eu

PACKAGES="texlive-latex-base texlive-latex-recommended poppler-utils"

if command -v pdflatex >/dev/null 2>&1 && command -v pdftoppm >/dev/null 2>&1; then
    exit 0
fi

if ! command -v apt-get >/dev/null 2>&1; then
    echo "install-latex.sh: no apt-get here; install pdflatex (TeX Live: $PACKAGES) by hand" >&2
    exit 1
fi

if [ "$(id -u)" -eq 0 ]; then
    SUDO=""
elif command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
else
    echo "install-latex.sh: not root and no sudo; install as root: apt-get install $PACKAGES" >&2
    exit 1
fi

echo "install-latex.sh: installing $PACKAGES (a few minutes) ..." >&2
$SUDO apt-get update -qq
# shellcheck disable=SC2086  # the package list is meant to split
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $PACKAGES >/dev/null
command -v pdflatex >/dev/null 2>&1 && command -v pdftoppm >/dev/null 2>&1
