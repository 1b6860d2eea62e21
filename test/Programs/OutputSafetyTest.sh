#!/usr/bin/env bash
# Output safety of ffd-match and ffd-voxelize (docs/ffd-match.md, "Limits and errors"): no output replaces an input, a
# failed write never exits 0 and leaves nothing behind, devices and FIFOs are written into, never replaced, several
# outputs are committed together or not at all, and every output is checked before any work.
#
#   OutputSafetyTest.sh CASE FFD_MATCH FFD_VOXELIZE MESH WORK_DIR
#
# Each CASE prints "PASS: ..." and exits 0 when the program behaved as promised; otherwise it says what went wrong
# and exits 1.
set -u
case_name=$1
match=$2
voxelize=$3
mesh=$4
work=$5/$case_name
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1

fail() {
  echo "FAIL: $*"
  exit 1
}
# Runs the command, keeps its exit code in $status and its stderr in $work/stderr.
run() {
  "$@" > stdout 2> stderr
  status=$?
  cat stderr
}
expect_refusal() { # PATTERN: non-zero exit; the last stderr line is the one error line and matches PATTERN
  [ "$status" -ne 0 ] || fail "exit code 0, expected a refusal"
  [ "$(grep -c 'error:' stderr)" -eq 1 ] || fail "expected exactly one error line on stderr"
  tail -n 1 stderr | grep -Eq -- "$1" || fail "the message does not match '$1'"
}
expect_early_refusal() { # PATTERN: refused before any work: stderr is the one error line
  expect_refusal "$1"
  [ "$(wc -l < stderr)" -le 1 ] || fail "more than one line on stderr: the refusal came after some work"
}
no_leftovers() { # no temporary file of the programs in the folder
  if ls -A | grep -Eq '^\.ffd-(match|voxelize)-'; then
    fail "temporary files left behind: $(ls -A | grep -E '^\.ffd-' | tr '\n' ' ')"
  fi
}
same_bytes() { # FILE COPY
  cmp -s "$1" "$2" || fail "$1 was changed"
}

cp "$mesh" s.off
cp "$mesh" t.off
cp s.off s.orig
cp t.off t.orig
go=(--method go --grid 4 --levels 1 --iterations 3 --voxel-size 0.5)

case "$case_name" in
  OutputIsSource)
    run "$match" --source s.off --target t.off "${go[@]}" --output s.off
    expect_early_refusal "--output 's.off' is the input 's.off'"
    same_bytes s.off s.orig
    ;;
  OutputIsTarget)
    run "$match" --source s.off --target t.off "${go[@]}" --output t.off
    expect_early_refusal "is the input 't.off'"
    same_bytes t.off t.orig
    ;;
  ReportIsSource)
    run "$match" --source s.off --target t.off "${go[@]}" --output o.off --report s.off
    expect_early_refusal "--report 's.off' is the input"
    same_bytes s.off s.orig
    [ ! -e o.off ] || fail "o.off was written"
    ;;
  OutputIsHardLinkOfSource)
    ln s.off link.off
    run "$match" --source s.off --target t.off "${go[@]}" --output link.off
    expect_early_refusal "is the input 's.off' \(the same file\)"
    same_bytes s.off s.orig
    ;;
  OutputIsSymlinkToTarget)
    ln -s t.off link.off
    run "$match" --source s.off --target t.off "${go[@]}" --output link.off
    expect_early_refusal "is the input 't.off'"
    same_bytes t.off t.orig
    [ -L link.off ] || fail "the symbolic link was replaced"
    ;;
  OutputIsSymlinkToOtherFile)
    # A symbolic link to a file that is no input is written through: the file is replaced, the link stays.
    mkdir elsewhere
    echo previous > elsewhere/o.off
    ln -s elsewhere/o.off link.off
    run "$match" --source s.off --target t.off "${go[@]}" --output link.off
    [ "$status" -eq 0 ] || fail "exit code $status"
    [ -L link.off ] || fail "the symbolic link was replaced by a file"
    head -1 elsewhere/o.off | grep -q '^OFF' || fail "the file the link names was not written"
    ln -s no-such-file dangling.off
    run "$match" --source s.off --target t.off "${go[@]}" --output dangling.off
    expect_early_refusal "cannot write --output 'dangling.off': a symbolic link to nothing"
    no_leftovers
    ( cd elsewhere && no_leftovers )
    ;;
  OutputIsReport)
    run "$match" --source s.off --target t.off "${go[@]}" --output o.off --report o.off
    expect_early_refusal "--report and --output name the same file"
    [ ! -e o.off ] || fail "o.off was written"
    ;;
  VoxelizeReportIsMesh)
    run "$voxelize" s.off o.nrrd --mode solid --voxel-size 0.5 --report s.off
    expect_early_refusal "--report 's.off' is the input"
    same_bytes s.off s.orig
    [ ! -e o.nrrd ] || fail "o.nrrd was written"
    ;;
  VoxelizeReportInMissingFolder)
    run "$voxelize" s.off o.nrrd --mode solid --voxel-size 0.5 --report no-such-folder/r.json
    expect_early_refusal "cannot write --report 'no-such-folder/r.json': the folder does not exist"
    [ ! -e o.nrrd ] || fail "o.nrrd was left although the run failed"
    no_leftovers
    ;;
  ReportIsFolder)
    echo previous > o.off
    mkdir r.json
    run "$match" --source s.off --target t.off "${go[@]}" --output o.off --report r.json
    expect_early_refusal "cannot write --report 'r.json': it is a folder"
    [ "$(cat o.off)" = previous ] || fail "the existing o.off was replaced"
    no_leftovers
    ;;
  UpperCaseExtension)
    run "$match" --source s.off --target t.off "${go[@]}" --output OUT.OFF --transform-out T.TFM
    [ "$status" -eq 0 ] || fail "exit code $status"
    head -1 OUT.OFF | grep -q '^OFF' || fail "OUT.OFF is not an OFF file"
    grep -q 'BSplineTransform' T.TFM || fail "T.TFM is not a transform file"
    no_leftovers
    ;;
  TransformWithoutWriter)
    start=$(date +%s%N)
    run "$match" --source s.off --target t.off --method go --grid 20 --voxel-size 0.01 --output o.off \
      --transform-out t.json
    expect_early_refusal "--transform-out must name a transform file ITK can write .*'t.json'"
    elapsed=$(( ($(date +%s%N) - start) / 1000000 ))
    [ "$elapsed" -lt 5000 ] || fail "refused only after ${elapsed} ms: the check must come before any work"
    ! grep -q '\.ffd-match-' stderr || fail "the message names the temporary file"
    [ ! -e o.off ] || fail "o.off was written"
    no_leftovers
    ;;
  FileSizeLimitKills)
    # SIGXFSZ kills the run at the limit: nothing may be left, not even the temporary file.
    # (The output goes through a pipe: the limit applies to regular files only.)
    (ulimit -f 0; exec "$match" --source s.off --target t.off "${go[@]}" --output o.vtk --report r.json) 2>&1 \
      | cat > stderr
    status=${PIPESTATUS[0]}
    [ "$status" -ne 0 ] || fail "exit code 0 under a file size limit of 0"
    [ ! -e o.vtk ] && [ ! -e r.json ] || fail "an output was left"
    no_leftovers
    ;;
  FileSizeLimitIgnored)
    # SIGXFSZ ignored: writes past the limit fail (EFBIG); the cut file must be noticed.
    (trap '' XFSZ; ulimit -f 0; exec "$match" --source s.off --target t.off "${go[@]}" --output o.off) 2>&1 \
      | cat > stderr
    status=${PIPESTATUS[0]}
    cat stderr
    [ "$status" -ne 0 ] || fail "exit code 0 although the output could not be written whole"
    [ ! -e o.off ] || fail "a cut o.off was left"
    no_leftovers
    ;;
  FullFileSystem)
    # A 64 kB file system in a private mount namespace (root), filled up: the run's outputs do not fit.
    if ! unshare -m true 2> /dev/null; then
      fail "cannot make a private mount namespace here (needs root and unshare)"
    fi
    mkdir full
    unshare -m bash -c "mount -t tmpfs -o size=64k tmpfs full && head -c 65536 /dev/zero > full/filler; \
      '$match' --source s.off --target t.off ${go[*]} --output full/o.vtk --transform-out full/t.tfm \
      --report full/r.json > stdout 2> stderr; echo \$? > status; ls -A full > listing"
    status=$(cat status)
    cat stderr
    [ "$status" -ne 0 ] || fail "exit code 0 on a full file system"
    [ "$(cat listing)" = filler ] || fail "files left on the full file system: $(tr '\n' ' ' < listing)"
    ;;
  ReportToNullDevice)
    mknod null c 1 3 || fail "cannot make a device node here (needs root)"
    run "$match" --source s.off --target t.off "${go[@]}" --output o.off --report null
    [ "$status" -eq 0 ] || fail "exit code $status"
    [ -c null ] || fail "the device was replaced by a regular file"
    [ -s o.off ] || fail "o.off was not written"
    no_leftovers
    ;;
  ReportToFullDevice)
    echo previous > o.off
    mknod full c 1 7 || fail "cannot make a device node here (needs root)"
    run "$match" --source s.off --target t.off "${go[@]}" --output o.off --report full
    expect_refusal "cannot write --report 'full'"
    [ -c full ] || fail "the device was replaced by a regular file"
    [ "$(cat o.off)" = previous ] || fail "o.off was replaced although the report failed"
    no_leftovers
    ;;
  ReportToFifo)
    mkfifo fifo
    cat fifo > fifo-content &
    reader=$!
    run "$match" --source s.off --target t.off "${go[@]}" --output o.off --report fifo
    wait "$reader"
    [ "$status" -eq 0 ] || fail "exit code $status"
    [ -p fifo ] || fail "the FIFO was replaced"
    grep -q '"program": "ffd-match"' fifo-content || fail "the report did not reach the FIFO's reader"
    ;;
  ReportToFifoWithoutReader)
    mkfifo fifo
    run timeout 20 "$match" --source s.off --target t.off "${go[@]}" --output o.off --report fifo
    expect_early_refusal "cannot write --report 'fifo': the FIFO has no reader"
    [ -p fifo ] || fail "the FIFO was replaced"
    ;;
  *)
    fail "unknown case $case_name"
    ;;
esac
echo "PASS: $case_name"
