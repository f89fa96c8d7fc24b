#!/bin/sh
# test_version.sh — tools/version.sh, the version strata is built with, in a
# scratch git repository: the release of VERSION on the commit that set it,
# RELEASE-N-gHASH N commits later (HASH the commit's own), -dirty with an
# uncommitted change, a new release back to its bare number, and the bare
# release outside git (a tarball). Skipped where git is missing. TAP output.
. tests/tap.sh
if ! command -v git > /dev/null; then
    echo "1..0 # SKIP git is not installed"
    exit 0
fi
V=$PWD/tools/version.sh
mkdir "$T/tarball" "$T/repo"
echo 2.3.4 > "$T/tarball/VERSION"
check "outside git: the release alone" '[ "$(cd "$T/tarball" && sh "$V")" = 2.3.4 ]'
cd "$T/repo" || exit 1
git init -q . && git config user.email t@t && git config user.name t
echo 2.3.4 > VERSION && git add VERSION && git commit -qm release
check "on the commit that set VERSION: the release alone" '[ "$(sh "$V")" = 2.3.4 ]' "(got $(sh "$V"))"
echo a > a && git add a && git commit -qm one
echo b > b && git add b && git commit -qm two
hash=$(git log -1 --format=%h)
check "two commits later: 2.3.4-2-g<hash>" '[ "$(sh "$V")" = "2.3.4-2-g$hash" ]' "(got $(sh "$V"), hash $hash)"
echo c >> a
check "an uncommitted change: -dirty" '[ "$(sh "$V")" = "2.3.4-2-g$hash-dirty" ]' "(got $(sh "$V"))"
git checkout -q a
echo 2.4.0 > VERSION && git commit -qam "next release"
check "a new release: its number alone" '[ "$(sh "$V")" = 2.4.0 ]' "(got $(sh "$V"))"
echo "1..$n"
