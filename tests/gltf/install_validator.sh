#!/usr/bin/env bash
# Installs the pinned Khronos glTF validator (npm gltf-validator) into DIR (under the build
# tree, never the repository), unless that version is already there. Fails when npm fails.
#   install_validator.sh DIR VERSION
set -euo pipefail
dir=$1 version=$2
installed=$dir/node_modules/gltf-validator/package.json
if [ -f "$installed" ] && grep -q "\"version\": \"$version\"" "$installed"; then
  echo "gltf-validator $version already in $dir"
  exit 0
fi
command -v npm >/dev/null || { echo "install_validator: npm is missing (scripts/setup installs it)" >&2; exit 1; }
mkdir -p "$dir"
npm install --prefix "$dir" --no-save --no-audit --no-fund --no-package-lock \
  "gltf-validator@$version"
test -f "$installed"
echo "gltf-validator $version installed in $dir"
