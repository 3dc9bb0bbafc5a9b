#!/usr/bin/env bash
# make_meshlab_prefix.sh PREFIX MESHLAB MESHLABSERVER SYSTEM_LIB_DIR [OUR_PLUGIN.so ...]
# Builds (or refreshes) a private MeshLab prefix; see cmake/MeshLabPrefix.cmake.
set -euo pipefail
prefix="$1"; meshlab="$2"; server="$3"; syslib="$4"; shift 4
arch_rel="lib/$(basename "$(dirname "$syslib")")/meshlab"   # lib/x86_64-linux-gnu/meshlab
mkdir -p "$prefix/bin" "$prefix/$arch_rel/plugins"
# Copies, not links: the loader resolves $ORIGIN from the binary's real location.
for b in "$meshlab" "$server"; do
  if ! cmp -s "$b" "$prefix/bin/$(basename "$b")"; then cp -f "$b" "$prefix/bin/"; fi
done
ln -sfn "$syslib/libmeshlab-common.so" "$prefix/$arch_rel/libmeshlab-common.so"
for f in "$syslib"/libmeshlab-common.so.*; do [ -e "$f" ] && ln -sfn "$f" "$prefix/$arch_rel/$(basename "$f")"; done
# Drop links that no longer point anywhere (a renamed plugin of ours, say).
find "$prefix/$arch_rel/plugins" -xtype l -delete
for f in "$syslib"/plugins/*.so; do ln -sfn "$f" "$prefix/$arch_rel/plugins/$(basename "$f")"; done
for f in "$@"; do ln -sfn "$(realpath "$f")" "$prefix/$arch_rel/plugins/$(basename "$f")"; done
