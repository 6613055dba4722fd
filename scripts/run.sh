#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, and runs the main job.
# Until the HTTP service exists, that is the command-line tool mapping a corpus mesh
# (or a mesh given as the first argument) and printing its metrics.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
mesh=${1:-../shared/meshes/spot.obj}
mkdir -p out
name=$(basename "${mesh%.*}")
build/cli/spheremap map "$mesh" -o "out/$name.sphere.obj" --metrics "out/$name.metrics.json"
echo "wrote out/$name.sphere.obj and out/$name.metrics.json:"
cat "out/$name.metrics.json"
