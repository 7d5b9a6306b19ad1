#!/bin/sh
# parallel_sweep.sh ARTTRACK SCENARIO: a 2 x 2 sweep run whole, then as two
# shards that GNU parallel runs side by side (--shard I/2), merged with
# `arttrack merge`: the merged sweep.csv equals the whole one byte for byte.
arttrack=$1
scenario=$2
command -v parallel >/dev/null 2>&1 ||
  { echo "GNU parallel is not installed (tools/setup.sh installs it)"; exit 1; }
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
# One sweep command for both: 1.5 s, one run per cell, a 160x120 camera, 8
# particles over a 40x30 likelihood; more options (--shard, --out) after.
cat >sweep.sh <<EOS
#!/bin/sh
exec timeout 240 "$arttrack" sweep "$scenario" --runs 1 --methods encoders_only,full_fusion \\
  --grid camera.drop_probability=0,1 --grid camera.latency_s=0,0.03 \\
  --set duration_s=1.5 --set camera.width=160 --set camera.height=120 \\
  --set "tracker_overrides={particle_filter.particles: 8, depth_model.width: 40, depth_model.height: 30}" \\
  "\$@"
EOS
chmod +x sweep.sh
./sweep.sh --out all >out.txt 2>&1 || { echo "the whole sweep failed:"; cat out.txt; exit 1; }
parallel --will-cite -j 2 ./sweep.sh --shard {}/2 --out parts/{} '>' parts_{}.txt '2>&1' ::: 0 1 ||
  { echo "a shard failed:"; cat parts_*.txt; exit 1; }
"$arttrack" merge parts/0 parts/1 --out merged >out.txt 2>&1 ||
  { echo "merge failed:"; cat out.txt; exit 1; }
# A header and the four cells, more than 1000 bytes (the gtest it replaces
# asked the size).
[ "$(wc -l <all/sweep.csv)" -gt 4 ] && [ "$(wc -c <all/sweep.csv)" -gt 1000 ] ||
  { echo "all/sweep.csv is too short:"; cat all/sweep.csv; exit 1; }
cmp all/sweep.csv merged/sweep.csv || { echo "the merged shards differ from the whole sweep"; exit 1; }
exit 0
