#!/usr/bin/env bash
# The commit --version names, from each place it can come from (src/results/source_commit.cmake):
# a git checkout read with git; a `git archive` of it read without git (the .git_archival.txt
# line export-subst fills in); a tree with neither says "unknown". And the built program prints
# the checkout's commit.
# Usage: source_commit_test.sh ASTROJAX SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"
script=$src/src/results/source_commit.cmake
define() { sed -n "s/^#define $1 \"\(.*\)\"$/\1/p" "$2"; }
if ! head=$(git -C "$src" rev-parse --short=12 HEAD 2> /dev/null); then
  echo "source_commit: $src is not a git checkout (or git is missing): the archive case cannot be made here"
  exit 77
fi

cmake -DSOURCE_DIR="$src" -DOUTPUT="$work/git.hpp" -P "$script"
check "checkout: the commit from git ($(define ASTROJAX_GIT_COMMIT "$work/git.hpp"), HEAD $head)" \
  "[ '$(define ASTROJAX_GIT_COMMIT "$work/git.hpp")' = '$head' ] && grep -q 'read from git' '$work/git.hpp'"
"$bin" --version > "$work/version.out" 2>&1
check "--version: the checkout's commit ($(cat "$work/version.out"))" \
  "grep -Eq '^astrojax [0-9]+\.[0-9]+\.[0-9]+ \(git commit [0-9a-f]{12}; ' '$work/version.out'"

# A source archive of HEAD, read with no git at all (GIT names a program that does not exist).
mkdir "$work/archive"
git -C "$src" archive HEAD | tar -x -C "$work/archive"
cmake -DSOURCE_DIR="$work/archive" -DOUTPUT="$work/archive.hpp" -DGIT="$work/no-git" -P "$script"
check "archive without git: HEAD's commit from .git_archival.txt ($(define ASTROJAX_GIT_COMMIT "$work/archive.hpp"))" \
  "[ '$(define ASTROJAX_GIT_COMMIT "$work/archive.hpp")' = '$head' ] && grep -q 'source archive' '$work/archive.hpp'"

# Neither: a copy of the tree whose .git_archival.txt was never filled in, without git.
mkdir "$work/plain"
cp "$src/.git_archival.txt" "$work/plain/"
cmake -DSOURCE_DIR="$work/plain" -DOUTPUT="$work/plain.hpp" -DGIT="$work/no-git" -P "$script"
check "no git, no archive: unknown, and says why" \
  "[ '$(define ASTROJAX_GIT_COMMIT "$work/plain.hpp")' = unknown ] && grep -q 'neither' '$work/plain.hpp'"

# Rewritten only when it changes: a build without a new commit recompiles nothing.
touch -d '2000-01-01' "$work/git.hpp"
cmake -DSOURCE_DIR="$src" -DOUTPUT="$work/git.hpp" -P "$script"
check "unchanged commit: the header is not rewritten" "[ \$(stat -c %Y '$work/git.hpp') -lt 1000000000 ]"
finish "source_commit"
