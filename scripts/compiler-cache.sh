# Sourced by the build scripts: compile through ccache when it is installed
# (install-deps.sh installs it), so a rebuild of sources that did not change, in a new
# clone or build folder too, is a cache hit instead of a compile. Paths are hashed
# relative to the checkout (CCACHE_BASEDIR), so clones in other folders share the cache.
# Read by CMake when it configures a build folder for the first time.
if command -v ccache > /dev/null; then
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache
  CCACHE_BASEDIR=$(pwd -P)
  export CCACHE_BASEDIR
fi
