#!/usr/bin/env bash
# Renders the depth-cue and stereo pictures of docs/viewing.md with `bump render`
# (offscreen; Mesa's CPU Vulkan where there is no GPU). Run from the crate
# root after `cargo build --release`: bash docs/images/render.sh
set -euo pipefail
bump=${BUMP:-target/release/bump}
pdb=../shared/pdb/6xg5_tmp_prepared.pdb
out=docs/images
common=(--ligand TOP --size 480x300 --view-turn 0,1,0,60 --zoom 1.6)
for cue in none depth outline ao shadow translucent depth,outline,ao,shadow; do
    name=${cue//,/+}
    "$bump" render "$pdb" "${common[@]}" --cue "$cue" -o "$out/cue-$name.png"
done
for mode in side-by-side side-by-side-half top-bottom top-bottom-half rows columns anaglyph frame-sequential; do
    "$bump" render "$pdb" "${common[@]}" --stereo "$mode" --eye-sep 0.06 -o "$out/stereo-$mode.png"
done
# docs/viewing.md: DHFR with trimethoprim, coloured by Vina contribution.
"$bump" render "$pdb" "${common[@]}" --color contribution --cue translucent -o "$out/fit-contribution.png"
# docs/viewing.md: the drug moved 5 Å out of its pocket (collisions off), its crystal pose as the ghost, in an 8 Å slab.
"$bump" render "$pdb" --ligand TOP --size 480x300 --zoom 2.2 --no-contacts --move 5,0,0 --ghost --slab 8 -o "$out/fit-ghost-slab.png"
# docs/viewing.md and the README: the pocket in ball-and-stick with hydrogen bonds.
"$bump" render "$pdb" --ligand TOP --size 480x300 --view-turn 0,1,0,60 --zoom 2.5 --sticks --hbonds --color contribution --cue depth,translucent -o "$out/fit-sticks.png"
