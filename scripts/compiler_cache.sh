# Sourced by build.sh, sanitize.sh and fuzz.sh: the compiler cache (ccache,
# installed by install_deps.sh) for their builds. The cache lives outside
# the clone (ccache's own folder, ~/.cache/ccache unless CCACHE_DIR says
# otherwise), so a fresh clone in another folder, as CI makes, still hits
# it: paths are hashed relative to the clone (CCACHE_BASEDIR) and the
# working directory is left out of debug builds' hashes (CCACHE_NOHASHDIR).
# Sets CACHE_ARGS to the CMake arguments that use it (none without ccache).
CACHE_ARGS=()
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true
  CACHE_ARGS=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
