#!/usr/bin/env bash
# Runs one loader fuzz target: tests/fuzz/run.sh BUILD_DIR PARSER SECONDS
# Corpus: the small seeds in seeds/<parser>/, the regression inputs, and (when ../shared is there) the
# real files of that format (cut to FUZZ_MAX_LEN bytes: 4 MiB for the compressed formats, 64 KiB for the
# others, so mutation stays fast; the unit suite loads them whole). New corpus entries and crashes go to BUILD_DIR/fuzz/<parser>/.
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
# Parsers that read gzip, zlib or bzip2 get inputs up to 4 MiB, so a decompression bomb (a stream that
# expands 1000-fold and more) is within the fuzzer's reach; the others stay at 64 KiB.
case $parser in
  nrrd | raw_name | metaimage | nifti) max_len=${FUZZ_MAX_LEN:-4194304} ;;
  *) max_len=${FUZZ_MAX_LEN:-65536} ;;
esac
# rss/malloc limits: a loader must refuse a lying header before allocating gigabytes. The loaders' memory
# budget is set to half the fuzzer's limit, so a claim they accept fits it and one they refuse is a
# LoadError, not a finding.
export SPLATLAB_MEMORY_BUDGET_MB=${SPLATLAB_MEMORY_BUDGET_MB:-1024}
exec "$build/tests/fuzz/fuzz_$parser" "$work/corpus" -artifact_prefix="$work/artifacts/" \
  -max_total_time="$seconds" -max_len="$max_len" -rss_limit_mb=2048 -timeout=20 \
  -print_final_stats=1
