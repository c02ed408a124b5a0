#!/usr/bin/env bash
# Runs one loader fuzz target: tests/fuzz/run.sh BUILD_DIR PARSER SECONDS
# Corpus: the small seeds in seeds/<parser>/, the regression inputs, and (when ../shared is there) the
# real files of that format (cut to FUZZ_MAX_LEN bytes, 64 KiB by default, so mutation stays fast; the
# unit suite loads them whole). New corpus entries and crashes go to BUILD_DIR/fuzz/<parser>/.
set -euo pipefail
build=$1 parser=$2 seconds=${3:-600}
here=$(cd "$(dirname "$0")" && pwd)
shared=${SPLATLAB_DATA_DIR:-$here/../../../shared/data/volumes}
work=$build/fuzz/$parser
mkdir -p "$work/corpus" "$work/artifacts"
cp -n "$here/seeds/$parser/"* "$work/corpus/" 2>/dev/null || true
cp -n "$here/regressions/$parser/"* "$work/corpus/" 2>/dev/null || true
if [ -d "$shared" ]; then
  case $parser in
    nrrd) cp -n "$shared/tooth.nrrd" "$work/corpus/" ;;
    metaimage) cp -n "$shared/originals/LIDC2.mha" "$shared/originals/HeadMRVolume.mhd" "$work/corpus/" ;;
    nifti) cp -n "$shared/originals/avg152T1_RL_nifti.nii.gz" "$work/corpus/" ;;
    slc) cp -n "$shared/originals/neghip.slc" "$work/corpus/" ;;
    tf) cp -n "$here/../../assets/presets/"*.json "$work/corpus/" ;;
  esac
fi
# rss/malloc limits: a loader must refuse a lying header before allocating gigabytes.
exec "$build/tests/fuzz/fuzz_$parser" "$work/corpus" -artifact_prefix="$work/artifacts/" \
  -max_total_time="$seconds" -max_len="${FUZZ_MAX_LEN:-65536}" -rss_limit_mb=2048 -timeout=20 \
  -print_final_stats=1
