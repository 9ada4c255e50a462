#!/usr/bin/env bash
# An engine adapter's ideal joints (docs/engines.md, "Ideal joints") against flexref's CVODE
# reference, end to end:
#   - every joint kind the engine maps, in the tree and closing loops (the scenes of
#     examples/engine_adapter/joint_scenes/, each mechanism a few tenths of a second), with a
#     spring, Andrews' squeezer (ten revolute joints, three loops, a spring, a motor) and, where
#     the engine drives joints, the driven slider-crank: at steps h and h/2 the error
#     (rotation+points) converges at the integrator's order (a dropped or misplaced joint leaves
#     an error that does not shrink with h), the tree's joints stay closed to round-off and
#     compare finds the run on its joints;
#   - every scene key the engine cannot map is refused: exit 1, the key named, no file written.
# Usage: joints_test.sh FLEXREF ADAPTER ENGINE   (ENGINE: mujoco | simbody; from the repository
#        root)
set -uo pipefail
flexref=$1
adapter=$2
engine=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { passed=$((passed + 1)); }
scenes=examples/engine_adapter/joint_scenes

# The integrator and the order its errors must show between h and h/2: MuJoCo's RK4 is second
# order in a body's attitude (docs/engines.md) and so in these scenes' rotations; Simbody's
# RK3 third. A lower bound p - 0.5 on log2(e(h)/e(h/2)): half an order below the claim still
# separates a convergent run (ratio 2^p) from one whose error is a joint's (ratio 1).
if [[ $engine == mujoco ]]; then
  integrator=rk4 order=2
else
  integrator=rk3 order=3
fi

# A scene's CVODE reference at rtol 1e-12 (its sidecar names the scene: compare measures the
# joints on it).
reference() { "$flexref" reference "$1" --solver cvode --rtol 1e-12 --no-estimate -o "$2" >/dev/null; }

# compare --json of a run: "error off_joints tree_violation loop_violation" (the error in
# rotation+points, rad + m: the bounds below are in metres and radians), the largest
# violations of the tree's joints (those in $3, a comma-separated list) and of the others.
measure() {
  "$flexref" compare --json --metric rotation+points "$1" "$2" | /usr/bin/python3 -c '
import json, sys
d = json.load(sys.stdin)
tree = sys.argv[1].split(",")
v = [j["violation"] for j in d["joints"] if j["name"] in tree]
w = [j["violation"] for j in d["joints"] if j["name"] not in tree]
print(d["metric"]["value"], d["off_joints"], max(v) if v else 0.0, max(w) if w else 0.0)' "$3"
}

# Values written with 17 significant digits at coordinates up to 10 m carry 1e-15 m of
# rounding; the engines compose a tree's poses from its joint coordinates afresh at every step,
# so a tree joint shows that rounding and nothing more: 1e-13, a hundredfold margin.
round_off=1e-13

# check SCENE NAME H TREE_JOINTS [END_TIME [OPTIONS [KINEMATIC]]]: the two runs (the adapter
# given OPTIONS too), their order, the joints' violations. KINEMATIC: a mechanism without
# degrees of freedom, whose motion the joints and drives alone decide: its error is bounded
# instead of converging.
check() {
  local scene=$1 name=$2 h=$3 tree=$4 end=${5:-} options=${6:-} kinematic=${7:-}
  local file=$tmp/$name.toml
  if [[ -n $end ]]; then
    sed "s/^end_time = .*/end_time = $end/" "$scene" >"$file"
  else
    cp "$scene" "$file"
  fi
  reference "$file" "$tmp/$name.ref.csv" || { fail "$name: reference"; return; }
  local h2
  h2=$(awk -v h="$h" 'BEGIN { printf "%.17g", h / 2 }')
  local e=() off=() tree_v=() loop_v=()
  for step in "$h" "$h2"; do
    # shellcheck disable=SC2086
    if ! "$adapter" "$file" "$step" "$tmp/$name.$step.csv" --integrator "$integrator" $options \
      >/dev/null 2>"$tmp/err"; then
      fail "$name at h = $step: $(cat "$tmp/err")"
      return
    fi
    read -r err o v w <<<"$(measure "$tmp/$name.$step.csv" "$tmp/$name.ref.csv" "$tree")"
    e+=("$err") off+=("$o") tree_v+=("$v") loop_v+=("$w")
  done
  converges() { # E1 E2: log2(E1/E2) > order - 0.5, or both at round-off
    awk -v a="$1" -v b="$2" -v p="$order" -v r="$round_off" \
      'BEGIN { exit !((a <= r && b <= r) || (b > 0 && log(a / b) / log(2) > p - 0.5)) }'
  }
  if [[ -n $kinematic ]]; then
    # Projected onto its joints at every step to 1e-10 (--constraint-tolerance), the kinematic
    # motion is the closed form's to that tolerance, whatever the step: 1e-9 allows the
    # reference's own error (CVODE at rtol 1e-12: 1e-11 on this scene) and the projection's.
    for err in "${e[@]}"; do
      awk -v a="$err" 'BEGIN { exit !(a <= 1e-9) }' && ok || fail "$name: error $err above 1e-9"
    done
  else
    converges "${e[0]}" "${e[1]}" && ok ||
      fail "$name: errors ${e[0]}, ${e[1]} at h = $h, $h2 do not converge at order $order"
  fi
  for v in "${tree_v[@]}"; do
    awk -v v="$v" -v r="$round_off" 'BEGIN { exit !(v <= r) }' && ok ||
      fail "$name: a tree joint is off by $v"
  done
  # A loop closure is held by the engine's constraint solver: MuJoCo's soft constraints (their
  # time constant 2h by default) and Simbody's projection leave a violation that shrinks with
  # the step like the error; a closure that does not hold leaves one that does not.
  if [[ -n $kinematic ]]; then
    for w in "${loop_v[@]}"; do
      awk -v v="$w" 'BEGIN { exit !(v <= 1e-10) }' && ok || fail "$name: a loop is off by $w"
    done
  else
    converges "${loop_v[0]}" "${loop_v[1]}" && ok ||
      fail "$name: loop violations ${loop_v[0]}, ${loop_v[1]} at h = $h, $h2 do not converge"
  fi
  # Without loops the run must be on its joints (compare's verdict, trajectory/joint_violation).
  if [[ ${loop_v[1]} == 0.0 ]]; then
    [[ ${off[1]} == False ]] && ok || fail "$name at h = $h2: compare finds the run off its joints"
  fi
}

check "$scenes/tree_kinds.toml" tree_kinds 0.002 guide,hinge,weld,cross,sleeve_axis,shoulder
check "$scenes/loop_kinds.toml" loop_kinds 0.002 O1,O2,bob_pivot,h1,h2,A,B,D
if [[ $engine == mujoco ]]; then
  # MuJoCo's tree takes the prismatic, universal and cylindrical joints; the loops close at Q,
  # bell_ball and wheel_hinge.
  check "$scenes/loop_kinds_more.toml" loop_kinds_more 0.002 O,P,guide,bell_cross,wheel_sleeve
else
  check "$scenes/loop_kinds_more.toml" loop_kinds_more 0.002 O,P,Q,bell_ball,wheel_hinge
  check scenes/slider_crank.toml slider_crank 0.001 O,P,Q 0.05 "--constraint-tolerance 1e-10" \
    kinematic
fi
# Andrews' squeezer: its tree of seven revolute joints, three revolute loops, spring and motor.
check scenes/andrews_squeezer.toml andrews 2e-5 O,F,B,A5,A7,G,H 0.01

# Refusals: each scene below has one part the engine cannot map; the adapter must name its key,
# exit 1 and write nothing.
base='[scene]
name = "refusal"
end_time = 0.1
output_step = 0.05
gravity = [0.0, 0.0, -9.81]

[[body]]
name = "a"
mass = 1.0
inertia = [0.1, 0.1, 0.1]
center_of_mass = [0.0, 0.0, -0.5]
'
ideal() { # NAME KIND AXIS_A [AXIS_B]
  printf '\n[[joint]]\nname = "%s"\nmodel = "ideal"\nkind = "%s"\nbody_a = "a"\npoint_a = [0.0, 0.0, 0.0]\nbody_b = "ground"\npoint_b = [0.0, 0.0, 0.0]\naxis_a = %s\naxis_b = %s\n' \
    "$1" "$2" "$3" "${4:-$3}"
}
refuse() { # NAME KEY [DT] (the scene in $tmp/NAME.toml)
  local out code
  out=$("$adapter" "$tmp/$1.toml" "${3:-0.01}" "$tmp/$1.csv" 2>&1)
  code=$?
  [[ $code -eq 1 && $out == *"key '$2'"* ]] && ok || fail "refusal $1: exit $code, $out"
  [[ -z $(find "$tmp" -maxdepth 1 -name "*$1.csv*") ]] && ok || fail "refusal $1 left a file"
}
contact_law() { # NAME RADIUS LAW_LINES: a sphere on the floor z = -1
  { echo "$base"; printf '[[contact]]\nkind = "sphere-plane"\nbody = "a"\ncenter = [0.0, 0.0, 0.0]\nradius = %s\nplane_point = [0.0, 0.0, -1.0]\nplane_normal = [0.0, 0.0, 1.0]\n%b' "$2" "$3"; } >"$tmp/$1.toml"
}

{ echo "$base"; printf '[[joint]]\nkind = "revolute"\nbody_a = "a"\npoint_a = [0.0, 0.0, 0.0]\nbody_b = "ground"\npoint_b = [0.0, 0.0, 0.0]\naxis_a = [0.0, 1.0, 0.0]\naxis_b = [0.0, 1.0, 0.0]\n'; } >"$tmp/revolute_bushing.toml"
{ echo "$base"; printf '[[joint]]\nkind = "spherical"\nbody_a = "a"\npoint_a = [0.0, 0.0, 0.0]\nbody_b = "ground"\npoint_b = [0.0, 0.0, 0.0]\ndamping = 1.0\n'; } >"$tmp/damped_bushing.toml"
{ echo "$base"; printf '[[potential]]\nkind = "point_charge"\nalpha = 1.0\nbeta = 0.3\nattractor = [0.0, 0.0, -1.0]\ncharges = [{ body = "a", at = [0.5, 0.0, 0.5], weight = 1.0 }]\n'; } >"$tmp/potential.toml"
refuse revolute_bushing "joint[1]"
refuse damped_bushing "joint[1]"
refuse potential "potential[1]"
# A flexible body (the check comes before a prescribed body's: a prescribed body is flexible).
cp scenes/rotating_cantilever.toml "$tmp/flexible.toml" && refuse flexible "body[1]"
if [[ $engine == mujoco ]]; then
  # A drive, and loops closed by a prismatic, cylindrical or universal joint: no MuJoCo
  # equality constraint holds them (both joints of each pair are tree-only in MuJoCo).
  contact_law contact 0.1 ''
  refuse contact "contact[1]"
  cp scenes/slider_crank.toml "$tmp/drive.toml" && refuse drive "joint[1].drive" 0.001
  for kind in prismatic cylindrical universal; do
    # Assembled at the start: a universal joint's two axes perpendicular, the others' parallel.
    axis_a='[1.0, 0.0, 0.0]'
    [[ $kind == universal ]] && axis_a='[0.0, 1.0, 0.0]'
    { echo "$base"; ideal first "$kind" "$axis_a" '[1.0, 0.0, 0.0]'
      ideal second "$kind" "$axis_a" '[1.0, 0.0, 0.0]'; } >"$tmp/${kind}_loop.toml"
    refuse "${kind}_loop" "joint[2]"
  done
else
  # A distance joint can only close a loop; a driven joint only be a mobilizer: a driven joint
  # whose two bodies another driven joint joins already is refused.
  { echo "$base"; echo 'angular_velocity = [0.0, 0.0, 1.0]'
    ideal first revolute '[0.0, 0.0, 1.0]'; printf 'drive = { law = "constant-rate", rate = 1.0 }\n'
    ideal second revolute '[0.0, 0.0, 1.0]'; printf 'drive = { law = "constant-rate", rate = 1.0 }\n'; } >"$tmp/driven_loop.toml"
  refuse driven_loop "joint[2]"
  contact_law linear_law 0.1 'law = "linear"\nrestitution = 0.5\n'
  contact_law exponent 0.1 'exponent = 1.2\n'
  contact_law friction 0.1 'friction = 0.3\n'
  contact_law point 0.0 ''
  { echo "$base"; printf '[[contact]]\nkind = "gap-support"\nbody = "a"\npoint = [0.0, 0.0, 0.0]\naxis_point = [0.0, 0.0, 0.0]\naxis = [1.0, 0.0, 0.0]\nclearance = 0.01\n'; } >"$tmp/gap.toml"
  { echo "$base"; printf '[[body]]\nname = "b"\nmass = 1.0\ninertia = [0.1, 0.1, 0.1]\nposition = [1.0, 0.0, 0.0]\n\n[[contact]]\nkind = "sphere-sphere"\nbody = "a"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.1\nbody_b = "b"\ncenter_b = [0.0, 0.0, 0.0]\nradius_b = 0.1\n'; } >"$tmp/sphere_sphere.toml"
  for name in linear_law exponent friction point gap sphere_sphere; do refuse "$name" "contact[1]"; done
fi

echo "$(basename "$adapter") joints: $passed passed, $failures failed"
((failures == 0))
