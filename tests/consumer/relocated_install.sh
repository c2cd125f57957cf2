#!/usr/bin/env bash
# relocated_install.sh PREFIX WORKDIR [SOURCE_ROOT]: copies the install tree PREFIX into WORKDIR and
# runs the copied tool there (bundled hand by name, bundled object, inspect, one regression case,
# a reach with the bundled robot),
# so the installed tool needs neither the source tree nor its original location. With SOURCE_ROOT,
# no installed binary or library may contain that path.
set -euo pipefail
prefix="$1"; work="$2"; src="${3:-}"
rm -rf "$work"; mkdir -p "$work"
cp -a "$prefix" "$work/prefix"
tm="$work/prefix/bin/taskmap"
cd "$work"
if [ -n "$src" ]; then
  if grep -rlF "$src" "$work/prefix/bin" "$work/prefix/lib"; then
    echo "relocated_install: the files above refer to the source tree $src" >&2
    exit 1
  fi
fi
unset TASKMAP_DATA_DIR
"$tm" --version
"$tm" build --object "$work/prefix/share/taskmap/objects/box.obj" --hand panda --valid 20 --seed 1 \
  --threads 1 -o "$work/box_panda.h5"
"$tm" inspect "$work/box_panda.h5" >/dev/null
"$tm" regress --only box_panda --threads 1
"$tm" reach --target "-0.07 0 0.02 0.7071068 0 0.7071068 0" >/dev/null  # bundled Panda + humanoid hand
echo "relocated_install: ok"
