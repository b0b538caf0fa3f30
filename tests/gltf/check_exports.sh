#!/usr/bin/env bash
# brdf export --to gltf of fits that take each branch of the glTF mapping (lambert: specular
# off; ggx conductor: metallic 1; ggx over a diffuse base: KHR_materials_specular; a power-cosine
# lobe is refitted as ggx and then takes one of those two, see Export.BlinnPhongIsRefitted...);
# every file must pass the Khronos validator with no errors.
#   check_exports.sh BRDF NODE_MODULES_DIR
set -euo pipefail
brdf=$1 modules=$2
here=$(cd "$(dirname "$0")" && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fit() { printf '{"model": "%s", "params": %s}\n' "$1" "$2" >"$scratch/$3.json"; }
fit lambert '{"rho_d": [0.8, 0.5, 0.2]}' lambert
fit ggx '{"rho_d": 0, "f0": [0.95, 0.64, 0.54], "alpha": 0.25}' metal
fit ggx '{"rho_d": [0.3, 0.1, 0.05], "f0": 0.05, "alpha": 0.08}' coated
files=()
for name in lambert metal coated; do
  "$brdf" export "$scratch/$name.json" --to gltf --out "$scratch/$name.gltf" >/dev/null
  files+=("$scratch/$name.gltf")
done
node "$here/validate_gltf.js" "$modules" "${files[@]}"
