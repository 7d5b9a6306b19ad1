#!/bin/sh
# hostile.sh ARTTRACK CLASS SOURCE_DIR: one class of hostile input (issue 29), made in a
# fresh folder. arttrack must answer within a second (the input's making is
# not timed; long_value within 3: yaml-cpp's parser alone reads its 1 MB
# value in about half a second on an idle 2-core machine, more while the
# suite runs beside it) with the exit code of its class and one short
# message naming the file and the item:
#   floating     a floating joint: refused at its line of the user's file
#   long_chain   2000 links in a chain: past the links limit (was a minute in
#                MuJoCo's compiler, then an error naming a temporary file)
#   deep_chain   100 joints deep: past the chain depth limit
#   huge_mesh    a binary STL declaring 5 000 001 triangles (a sparse file):
#                past the triangles limit before it is read
#   entity_bomb  nested XML entities (billion laughs): refused, naming the
#                file and the line
#   nested_xml   200 000 nested XML elements in a URDF (1.4 MB): urdfdom's
#                reader overflowed the stack on them
#   big_yaml     a 50 MB YAML value: past the YAML file limit, not parsed
#   long_value   a 1 MB YAML value: quoted shortened in the message
#   run_urdf     a URDF urdfdom refuses (a revolute joint without limits),
#                on the run path: the message names the file (it said "URDF
#                string")
arttrack=$1 class=$2 source_dir=$3
. "$(dirname "$0")/common.sh"

# expect CODE PATTERN COMMAND...: exit code, message (extended regular
# expression), at most $limit_s s (1 unless the class sets it) and 1000
# bytes of output.
expect() {
  code=$1 pattern=$2
  shift 2
  start=$(date +%s.%N)
  "$@" </dev/null >out.txt 2>&1
  got=$?
  seconds=$(echo "$start $(date +%s.%N)" | awk '{ printf "%.3f", $2 - $1 }')
  echo "$class: exit $got in $seconds s, $(wc -c <out.txt) bytes of output"
  [ "$got" -eq "$code" ] || fail "expected exit code $code, got $got"
  grep -Eq -- "$pattern" out.txt || fail "output does not match '$pattern'"
  awk -v s="$seconds" -v limit="${limit_s:-1}" 'BEGIN { exit !(s < limit) }' ||
    fail "took $seconds s, more than ${limit_s:-1} s"
  [ "$(wc -c <out.txt)" -lt 1000 ] || fail "more than 1000 bytes of output"
}

# scene FILE.urdf: a scene of that robot, its camera at its root link.
scene() {
  printf 'robot: {urdf: %s, end_effectors: [base_link]}\n' "$1" >scene.yaml
  printf 'camera: {link: base_link, width: 64, height: 48}\n' >>scene.yaml
}

# chain N: base_link and N links below it in one chain of fixed joints.
chain() {
  awk -v n="$1" 'BEGIN {
    print "<robot name=\"chain\"><link name=\"base_link\"/>"
    for (i = 0; i < n; ++i) {
      parent = i ? "l" (i - 1) : "base_link"
      printf "<link name=\"l%d\"/><joint name=\"j%d\" type=\"fixed\"><parent link=\"%s\"/>", i, i, parent
      printf "<child link=\"l%d\"/></joint>\n", i
    }
    print "</robot>"
  }'
}

case $class in
floating)
  cat >floating.urdf <<'EOF'
<robot name="r">
  <link name="base_link"/>
  <link name="body"/>
  <joint name="free" type="floating"><parent link="base_link"/><child link="body"/></joint>
</robot>
EOF
  scene floating.urdf
  expect 1 "floating.urdf:4: joint 'free' is floating" "$arttrack" render scene.yaml --out o
  ;;
long_chain)
  chain 2000 >long_chain.urdf
  scene long_chain.urdf
  expect 1 "long_chain.urdf: 2001 links, more than the 1000 arttrack takes" \
    "$arttrack" render scene.yaml --out o
  ;;
deep_chain)
  chain 100 >deep_chain.urdf
  scene deep_chain.urdf
  expect 1 "deep_chain.urdf: link 'l99' is 100 joints from the root, more than the 90" \
    "$arttrack" render scene.yaml --out o
  ;;
huge_mesh)
  # 80-byte header, then 5 000 001 (0x004C4B41, little-endian) triangles of
  # 50 bytes each, never written (a sparse file).
  { head -c 80 /dev/zero; printf '\101\113\114\000'; } >huge.stl
  truncate -s $((84 + 50 * 5000001)) huge.stl
  cat >huge.urdf <<'EOF'
<robot name="r">
  <link name="base_link"><visual><geometry><mesh filename="huge.stl"/></geometry></visual></link>
</robot>
EOF
  scene huge.urdf
  expect 1 "huge.urdf:2: link 'base_link' visual mesh 'huge.stl'.* 5000001 triangles" \
    "$arttrack" render scene.yaml --out o
  ;;
entity_bomb)
  {
    echo '<?xml version="1.0"?>'
    echo '<!DOCTYPE robot ['
    echo ' <!ENTITY lol "lol">'
    prev=lol
    for k in 1 2 3 4 5 6 7 8 9; do
      printf ' <!ENTITY lol%s "' $k
      for i in 1 2 3 4 5 6 7 8 9 10; do printf '&%s;' $prev; done
      echo '">'
      prev=lol$k
    done
    echo ']>'
    echo '<robot name="&lol9;"><link name="base_link"/></robot>'
  } >bomb.urdf
  scene bomb.urdf
  expect 1 "bomb.urdf: line 3: an XML entity declaration" "$arttrack" render scene.yaml --out o
  ;;
nested_xml)
  awk 'BEGIN {
    print "<robot name=\"r\">"
    print "<link name=\"base_link\"/>"
    for (i = 0; i < 200000; ++i) printf "<a>"
    for (i = 0; i < 200000; ++i) printf "</a>"
    print "</robot>"
  }' >nested.urdf
  scene nested.urdf
  expect 1 "nested.urdf: line 3: elements nested more than 100 deep" \
    "$arttrack" render scene.yaml --out o
  ;;
big_yaml)
  { printf 'methods: ['; head -c 52428800 /dev/zero | tr '\0' x; echo ']'; } >big.yaml
  expect 1 "big.yaml: [0-9]{8} bytes, more than the 4194304 a YAML file may have" \
    "$arttrack" run big.yaml --out o
  ;;
long_value)
  limit_s=3
  { printf 'scene: %s\nmethods: [' "$source_dir/models/scene_default.yaml"
    head -c 1048576 /dev/zero | tr '\0' x; echo ']'; } >long.yaml
  expect 1 "long.yaml: key 'methods': unknown method 'x{80}\.\.\.' \(1048576 characters\)" \
    "$arttrack" run long.yaml --out o
  ;;
run_urdf)
  cat >no_limit.urdf <<'EOF'
<robot name="r">
  <link name="base_link"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <link name="arm"/>
  <joint name="elbow" type="revolute"><parent link="base_link"/><child link="arm"/></joint>
</robot>
EOF
  scene no_limit.urdf
  printf 'scene: scene.yaml\nduration_s: 0.1\nmethods: [encoders_only]\n' >s.yaml
  expect 1 "cannot parse URDF file '[^']*no_limit.urdf': Joint \\[elbow\\] is of type REVOLUTE" \
    "$arttrack" run s.yaml --out o
  ;;
*)
  fail "unknown class '$class'"
  ;;
esac
exit 0
