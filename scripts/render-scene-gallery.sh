#!/bin/sh
# Renders the README's scene gallery into docs/scenes/ from the sample scenes (run from the repository root
# after building).
set -eu
mkdir -p docs/scenes
for scene in data-samples/*.toml; do
    name=$(basename "$scene" .toml)
    size=480x270
    [ "$name" = summit-panorama ] && size=960x320
    build/terracast scene "$scene" -o "docs/scenes/$name.png" --size "$size" --quiet
done
