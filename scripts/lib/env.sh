# Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
# Shared environment of the scripts/ entry points. Sourced, not run.

EFS_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
EFS_BUILD_DIR="${EFS_BUILD_DIR:-$EFS_ROOT/.build/ros}"
EFS_SHARED_DATA_DIR="${EFS_SHARED_DATA_DIR:-$(cd "$EFS_ROOT/.." && pwd)/shared/data}"
export EFS_ROOT EFS_BUILD_DIR EFS_SHARED_DATA_DIR

# The python3 on PATH may be a pyenv interpreter without rospkg; ROS tools need Debian's.
export PATH="/usr/bin:/bin:$PATH"
export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/ccache}"
export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-5G}"
# Relative paths in the cache key: a fresh clone elsewhere (CI) still hits the cache.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$EFS_ROOT}"
export CCACHE_NOHASHDIR=1
export EFS_JOBS="${EFS_JOBS:-$(nproc)}"

efs_log() { printf '[efs] %s\n' "$*" >&2; }

# Sources the catkin devel space (its scripts reference unset variables, hence set +u).
efs_source_devel() {
  local had_u=0
  [[ $- == *u* ]] && had_u=1
  set +u
  # shellcheck disable=SC1091
  source "$EFS_BUILD_DIR/devel/setup.bash"
  ((had_u)) && set -u
  return 0
}

# The real data (ed21, pittsburgh_mine) is read in place, never copied; a checkout that is not
# beside ../shared (a clone in /tmp, say) must be told where it is, or a dozen tests fail late.
efs_require_shared_data() {
  local missing=()
  local d
  for d in ed21 pittsburgh_mine; do
    [[ -d $EFS_SHARED_DATA_DIR/$d ]] || missing+=("$d/")
  done
  ((${#missing[@]} == 0)) && return 0
  efs_log "the real test data is not at EFS_SHARED_DATA_DIR=$EFS_SHARED_DATA_DIR" \
    "(missing ${missing[*]}); it is ../shared/data beside the checkout by default:" \
    "set EFS_SHARED_DATA_DIR to the folder holding ed21/ and pittsburgh_mine/"
  return 1
}

# Nothing was tested: still end with the summary line CI reads, and fail.
efs_untested() {
  echo "0 passed, 1 failed"
  exit 1
}

# "FAILED TOTAL" from ctest's summary line in the log $1; fails when ctest printed none.
efs_ctest_counts() {
  local summary
  summary=$(grep -E 'tests passed, [0-9]+ tests failed out of [0-9]+' "$1" | tail -1) || return 1
  [[ -n $summary ]] || return 1
  sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\1 \2/' <<<"$summary"
}
