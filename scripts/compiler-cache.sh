# Sourced by the build scripts: compile through ccache when it is installed
# (install-deps.sh installs it), so a rebuild of sources that did not change, in a new
# clone or build folder too, is a cache hit instead of a compile. Paths are hashed
# relative to the checkout (CCACHE_BASEDIR), so clones in other folders share the cache.
# Read by CMake when it configures a build folder for the first time.
# Without a usable cache folder (no HOME, a read-only one) it compiles as before.
if command -v ccache > /dev/null; then
  export CCACHE_DIR=${CCACHE_DIR:-${HOME:-/tmp}/.cache/ccache}
  if mkdir -p "$CCACHE_DIR" 2> /dev/null && [ -w "$CCACHE_DIR" ] && ccache -s > /dev/null 2>&1; then
    export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache
    CCACHE_BASEDIR=$(pwd -P)
    # The test programs precompile gtest's header: ccache caches such compiles only
    # with these two relaxations (its manual, "Precompiled headers").
    CCACHE_SLOPPINESS=pch_defines,time_macros
    # Compilers compared by content, not file time, so the container's build of the same
    # Debian compiler (docker/Dockerfile, with this cache mounted) hits what this one cached.
    CCACHE_COMPILERCHECK=content
    export CCACHE_BASEDIR CCACHE_SLOPPINESS CCACHE_COMPILERCHECK
  fi
fi
