#!/usr/bin/env bash
# What a resume makes of a damaged journal, and of an output another sweep is writing:
# - a flipped byte inside a result: that one result discarded and said so (bytes, reason,
#   count), every other kept, its task run again; the file equals an uninterrupted run's;
#   verify on the .part words the journal's damage in the same sentence;
# - a record header damaged (its length): the same, the next record found by its magic and CRC;
# - a flipped byte in the file's magic: reported as a damaged header, every result kept;
# - a flipped byte in the header record (the sweep's identity): refused as such, exit 2, the
#   journal left as it was (--force starts afresh);
# - the last record cut short: "cut short", that task runs again;
# - a second sweep on an output in use: "in use by another running sweep" with or without
#   --resume (and with --force); once the first is killed (kill -9) the kernel has released its
#   lock and a sweep on the output completes.
# Usage: journal_damage_test.sh ASTROJAX SOURCE_DIR
set -u
bin=$1; src=$2
source "$(dirname "$0")/check.sh"
cd "$work"
sweep=("$src/sweeps/quick.toml" -q --set protocol.windows_per_task=1 --set "grid.drive_radius=[0.01,0.015,0.02]")
same() { for g in /config /chains /windows /samples /tasks; do h5diff "$1" "$2" "$g" > /dev/null 2>&1 || return 1; done; }
# The byte offset of record $2 (0: the header record) of journal $1, and its payload length.
record() {
  /usr/bin/python3 - "$1" "$2" << 'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
at = 8
for _ in range(int(sys.argv[2])):
    at += 24 + struct.unpack_from('<Q', data, at + 16)[0]
print(at, struct.unpack_from('<Q', data, at + 16)[0])
PY
}
flip() { /usr/bin/python3 -c "import sys; f = open(sys.argv[1], 'r+b'); f.seek(int(sys.argv[2])); b = f.read(1); f.seek(int(sys.argv[2])); f.write(bytes([b[0] ^ 0x20]))" "$1" "$2"; }
interrupted() { rm -f "$1"*; "$bin" sweep "${sweep[@]}" -o "$1" --max-tasks 20 > /dev/null 2>&1; }

"$bin" sweep "${sweep[@]}" -o straight.h5 > straight.out 2>&1
check "uninterrupted run: exit 0" "[ $? -eq 0 ]"
tasks=$(h5dump -H -d /tasks/status straight.h5 2> /dev/null | grep -o 'DATASPACE  SIMPLE { ( [0-9]*' | grep -o '[0-9]*$')
check "the sweep has more tasks than the 20 an interrupted run leaves ($tasks)" "[ '${tasks:-0}' -gt 20 ]"

# A flipped byte in the middle of result 10's payload.
interrupted mid.h5
read -r at len < <(record mid.h5.journal 10)
flip mid.h5.journal $((at + 24 + len / 2))
"$bin" verify mid.h5.part > mid.verify 2>&1
check "flipped byte in a result: verify words the damage as the resume does ($(grep journal mid.verify))" \
  "grep -q 'mid.h5.journal: 19 results kept, 1 discarded (checksum mismatch at bytes $at-$((at + 24 + len)), 1 record); that task runs again' mid.verify"
"$bin" sweep "${sweep[@]}" -o mid.h5 --resume > mid.out 2>&1
check "flipped byte in a result: resume exit 0" "[ $? -eq 0 ]"
check "flipped byte in a result: 19 kept, 1 discarded, where and why ($(grep warning mid.out))" \
  "grep -q '19 results kept, 1 discarded (checksum mismatch at bytes $at-$((at + 24 + len)), 1 record); that task runs again' mid.out"
check "flipped byte in a result: the file equals the uninterrupted one" "same mid.h5 straight.h5"

# A flipped byte in result 5's length field: its framing is lost, the next record found.
interrupted length.h5
read -r at len < <(record length.h5.journal 5)
flip length.h5.journal $((at + 20))
"$bin" sweep "${sweep[@]}" -o length.h5 --resume > length.out 2>&1
check "damaged record header: resume exit 0, 19 kept, 1 discarded ($(grep warning length.out))" \
  "[ $? -eq 0 ] && grep -q '19 results kept, 1 discarded (damaged record header at bytes $at-' length.out"
check "damaged record header: the file equals the uninterrupted one" "same length.h5 straight.h5"

# A flipped byte in the file's magic: a damaged header, every record behind it kept.
interrupted magic.h5
flip magic.h5.journal 3
"$bin" sweep "${sweep[@]}" -o magic.h5 --resume > magic.out 2>&1
check "damaged magic: resume exit 0 and says the header is damaged, records kept ($(grep warning magic.out))" \
  "[ $? -eq 0 ] && grep -q 'its file header (the first 8 bytes) is damaged; the records behind it are intact and kept' magic.out && grep -q '(20 checksummed results)' magic.out"
check "damaged magic: the file equals the uninterrupted one" "same magic.h5 straight.h5"

# A flipped byte in the header record: its 20 results cannot be matched to this sweep.
interrupted identity.h5
read -r at len < <(record identity.h5.journal 0)
flip identity.h5.journal $((at + 24 + len / 2))
cp identity.h5.journal identity.before
"$bin" sweep "${sweep[@]}" -o identity.h5 --resume > identity.out 2>&1
rc=$?
check "damaged header record: exit 2, said as such (exit $rc: $(head -c 300 identity.out))" \
  "[ $rc -eq 2 ] && grep -q 'its header record (the sweep file and overrides it was started with, from byte 8) is damaged, so its 20 intact results cannot be matched' identity.out"
check "damaged header record: the journal left as it was" "cmp -s identity.h5.journal identity.before"
"$bin" sweep "${sweep[@]}" -o identity.h5 --force > /dev/null 2>&1
check "damaged header record: --force starts afresh and completes" "[ $? -eq 0 ] && same identity.h5 straight.h5"

# The last record cut short (an append killed half-way).
interrupted tail.h5
truncate -s $(($(stat -c %s tail.h5.journal) - 100)) tail.h5.journal
"$bin" sweep "${sweep[@]}" -o tail.h5 --resume > tail.out 2>&1
check "torn tail: resume exit 0, 19 kept, 1 discarded, cut short ($(grep warning tail.out))" \
  "[ $? -eq 0 ] && grep -q '19 results kept, 1 discarded (cut short at bytes' tail.out"
check "torn tail: the file equals the uninterrupted one" "same tail.h5 straight.h5"

# Two sweeps on one output: the second is told the output is in use, however it is asked.
slow=(--set integrator.method=rk4 --set integrator.step=2e-5)
"$bin" sweep "${sweep[@]}" "${slow[@]}" -o busy.h5 > busy.out 2>&1 &
first=$!
for _ in $(seq 1000); do [ -s busy.h5.journal ] && break; sleep 0.01; done
for how in "" --resume --force; do
  "$bin" sweep "${sweep[@]}" "${slow[@]}" -o busy.h5 $how > "busy$how.out" 2>&1
  rc=$?
  check "output in use, second sweep ${how:-without options}: exit 2, in use by another running sweep (exit $rc: $(head -c 200 "busy$how.out"))" \
    "[ $rc -eq 2 ] && grep -q 'busy.h5.journal is in use by another running sweep' 'busy$how.out'"
done
check "output in use: the first sweep still runs" "kill -0 $first 2> /dev/null"
kill -9 $first; wait $first 2> /dev/null
# Killed, it released its lock with its life: a new sweep on the output (the quick settings,
# --force over the unfinished one) is not refused and completes.
"$bin" sweep "${sweep[@]}" -o busy.h5 --force > busy.force 2>&1
rc=$?
check "first sweep killed (kill -9): its lock is gone, a sweep on the output completes (exit $rc)" \
  "[ $rc -eq 0 ] && same busy.h5 straight.h5 && ! grep -q 'in use' busy.force"
finish "journal_damage"
