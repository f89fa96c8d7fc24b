#!/bin/sh
# version.sh — prints the version `strata --version` shows and every file
# strata writes records: the release in the file VERSION (MAJOR.MINOR.PATCH),
# then, in a git checkout, git describe's distance from the commit that last
# changed VERSION: -N-gHASH N commits after it (g + the short hash of the
# commit built), and -dirty with uncommitted changes. On that commit, or
# outside git (a tarball), the release alone. Run from the source tree.
release=$(cat VERSION) || exit 1
base=$(git log -1 --format=%H -- VERSION 2> /dev/null)
if [ -z "$base" ]; then
    echo "$release"
    exit 0
fi
n=$(git rev-list --count "$base..HEAD")
version=$release
[ "$n" -gt 0 ] && version="$release-$n-g$(git rev-parse --short HEAD)"
git diff --quiet HEAD -- 2> /dev/null || version="$version-dirty"
echo "$version"
