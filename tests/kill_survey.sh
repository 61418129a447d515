#!/usr/bin/env bash
# How often does kill -9 of a sweep's master leave a .part that cannot be resumed correctly?
# Kills a 1-rank sweep (132 tasks; the master writes every task) N times at random points
# mid-sweep and resumes each twice: with the journal (as astrojax does) and from the .part
# alone (the journal removed, as before journals). Counts resumes that fail or whose file
# differs from an uninterrupted run (h5diff, all but /provenance). Not a ctest: a survey.
# Usage: tests/kill_survey.sh [ASTROJAX] [N]      (about 2 s per kill)
set -u
bin=$(realpath "${1:-build/astrojax}"); n=${2:-20}
src=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
sweep=("$src/sweeps/quick.toml" -q --set protocol.windows_per_task=1 --set "grid.drive_radius=[0.01,0.012,0.015,0.02]")
same() { for g in /config /chains /windows /samples /tasks; do h5diff "$1" "$2" "$g" > /dev/null 2>&1 || return 1; done; }
"$bin" sweep "${sweep[@]}" -o straight.h5 > /dev/null
killed=0; bad_journal=0; bad_part=0
for i in $(seq "$n"); do
  rm -f k.h5* j.h5*
  "$bin" sweep "${sweep[@]}" -o k.h5 &
  p=$!
  # Kill once the journal holds between ~200 kB and ~1.5 MB (of ~6 MB): mid-sweep.
  limit=$((200000 + RANDOM * 40))
  for _ in $(seq 2000); do [ "$(stat -c %s k.h5.journal 2> /dev/null || echo 0)" -gt $limit ] && break; sleep 0.005; done
  kill -9 $p; wait $p 2> /dev/null
  [ -e k.h5 ] && continue  # finished first
  killed=$((killed + 1))
  cp k.h5.part j.h5.part; cp k.h5.journal j.h5.journal
  rm k.h5.journal
  { "$bin" sweep "${sweep[@]}" -o k.h5 --resume && same k.h5 straight.h5; } > /dev/null 2>&1 || bad_part=$((bad_part + 1))
  { "$bin" sweep "${sweep[@]}" -o j.h5 --resume && same j.h5 straight.h5; } > /dev/null 2>&1 || bad_journal=$((bad_journal + 1))
done
echo "kill -9 of the master mid-sweep: $killed times"
echo "  resumed from the .part alone: $bad_part failed or differed from the uninterrupted run"
echo "  resumed with the journal:     $bad_journal failed or differed"
