#!/bin/bash
# Recreate issue 33's extra inputs (README.md beside this script): the real Robotiq 2F-85 with
# its collision meshes and four YCB scans, from git checkouts or mirrors of the two source
# repositories at the recorded commits, and the URDF and sidecar kept in this folder.
#
#   tests/bench/extra_real/setup.sh [--force] OBJECT_SIM_GIT ROBOTIQ_GIT [DEST]
#
# OBJECT_SIM_GIT: a clone (or bare mirror) of https://github.com/zerchen/object_sim holding
# commit $OBJECT_SIM_COMMIT; ROBOTIQ_GIT: one of https://github.com/ros-industrial/robotiq
# holding $ROBOTIQ_COMMIT. DEST defaults to ../extra_real beside the repository (where
# sampler_rate, grasp_sim_rate and trial_rate look by default). An existing DEST is replaced
# only with --force. Files are read with `git show COMMIT:path`, so neither checkout needs a work
# tree or to be at that commit.
set -euo pipefail

OBJECT_SIM_COMMIT=014ed2295076370054556a4c736d9dfa4c8ad952
ROBOTIQ_COMMIT=45196f6558fe8ba9d89bc8a105396c68c3e7e892
PKG=robotiq_2f_85_gripper_visualization
YCB_IDS=(005_tomato_soup_can 006_mustard_bottle 003_cracker_box 037_scissors)

usage() {
  sed -n '6p' "$0" | sed 's/^#  *//' >&2
  exit 2
}

force=0
args=()
for a in "$@"; do
  case "$a" in
    --force) force=1 ;;
    -h | --help) usage ;;
    -*) echo "setup.sh: unknown option $a" >&2; usage ;;
    *) args+=("$a") ;;
  esac
done
[ ${#args[@]} -eq 2 ] || [ ${#args[@]} -eq 3 ] || usage

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
object_sim=${args[0]}
robotiq=${args[1]}
dest=${args[2]:-$root/../extra_real}

for pair in "$object_sim:$OBJECT_SIM_COMMIT" "$robotiq:$ROBOTIQ_COMMIT"; do
  repo=${pair%:*}
  commit=${pair##*:}
  if ! git -C "$repo" cat-file -e "$commit^{commit}" 2>/dev/null; then
    echo "setup.sh: $repo is not a git repository holding commit $commit" >&2
    exit 1
  fi
done

dest_abs=$(realpath -m "$dest")
case "$dest_abs" in
  / | "$root" | "$root"/* | "$(realpath -m ~)")
    echo "setup.sh: refusing DEST $dest_abs (the root, the repository or home)" >&2
    exit 1
    ;;
esac
if [ -e "$dest_abs" ] && [ $force -eq 0 ]; then
  echo "setup.sh: $dest_abs exists; pass --force to replace it" >&2
  exit 1
fi

# Build beside DEST and move into place at the end: a failure leaves DEST as it was.
parent=$(dirname "$dest_abs")
mkdir -p "$parent"
tmp=$(mktemp -d "$parent/.extra_real.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

show() {  # show REPO COMMIT PATH OUT
  git -C "$1" show "$2:$3" >"$4"
}

# The YCB scans (google_16k, metres).
mkdir -p "$tmp/objects"
for id in "${YCB_IDS[@]}"; do
  show "$object_sim" $OBJECT_SIM_COMMIT "ycb/$id/textured.obj" "$tmp/objects/ycb_$id.obj"
done

# The hand: URDF, sidecar and licence from this folder; the package's collision meshes and
# package.xml from ros-industrial/robotiq, in a package folder beside the URDF (where taskmap's
# package:// lookup finds it: a folder above the URDF, or its child, named like the package).
hand="$tmp/hands/robotiq_2f85"
mkdir -p "$hand/$PKG/meshes/collision"
for f in robotiq_arg2f_85.urdf robotiq_arg2f_85.hand.json LICENSE; do
  cp "$here/hands/robotiq_2f85/$f" "$hand/$f"
done
show "$robotiq" $ROBOTIQ_COMMIT "$PKG/package.xml" "$hand/$PKG/package.xml"
meshes=$(git -C "$robotiq" ls-tree --name-only $ROBOTIQ_COMMIT "$PKG/meshes/collision/")
[ -n "$meshes" ] || { echo "setup.sh: no $PKG/meshes/collision in $robotiq" >&2; exit 1; }
for m in $meshes; do
  show "$robotiq" $ROBOTIQ_COMMIT "$m" "$hand/$PKG/meshes/collision/$(basename "$m")"
done

# The checked-in URDF must be what the xacro at the recorded commit expands to, and its
# licence the one at that commit.
/usr/bin/python3 "$here/expand_xacro.py" "$robotiq" $ROBOTIQ_COMMIT "$tmp/expanded.urdf"
if ! cmp -s "$tmp/expanded.urdf" "$hand/robotiq_arg2f_85.urdf"; then
  echo "setup.sh: $here/hands/robotiq_2f85/robotiq_arg2f_85.urdf differs from the expansion" \
    "of $ROBOTIQ_COMMIT (expand_xacro.py)" >&2
  exit 1
fi
rm "$tmp/expanded.urdf"
show "$robotiq" $ROBOTIQ_COMMIT LICENSE "$tmp/LICENSE.upstream"
if ! cmp -s "$tmp/LICENSE.upstream" "$hand/LICENSE"; then
  echo "setup.sh: hands/robotiq_2f85/LICENSE differs from ros-industrial/robotiq's" >&2
  exit 1
fi
rm "$tmp/LICENSE.upstream"
cp "$here/README.md" "$tmp/README.md"

chmod 755 "$tmp"
if [ -e "$dest_abs" ]; then
  old="$parent/.extra_real.old.$$"
  mv "$dest_abs" "$old"
  mv "$tmp" "$dest_abs"
  rm -rf "$old"
else
  mv "$tmp" "$dest_abs"
fi
trap - EXIT
echo "setup.sh: wrote $dest_abs"
find "$dest_abs" -type f | sort | sed "s|^$dest_abs/|  |"
