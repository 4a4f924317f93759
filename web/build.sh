#!/usr/bin/env bash
# Builds the WebAssembly decoder into BUILD_DIR/dist (pm_decoder.mjs + pm_decoder.wasm) with
# Debian's emscripten, from pm::codec's sources and zstd's decoder. zstd's sources come from
# Debian's source package (the zstd the native build links), fetched once into BUILD_DIR with
# a private apt configuration (a deb-src list of its own, nothing changed on the machine).
# Usage: web/build.sh [BUILD_DIR]   (default: build/web)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build/web}")
mkdir -p "$build"
export NODE_PATH=${NODE_PATH:-/usr/share/nodejs}

zstd_src="$build/zstd-src"
if [[ ! -d "$zstd_src/lib/decompress" ]]; then
  version=$(dpkg-query -W -f='${source:Version}' libzstd-dev)
  apt_dir="$build/apt"
  mkdir -p "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" "$build/zstd-package"
  # The release, its updates and its security updates: the zstd installed may come from any
  # (libzstd 1.5.4+dfsg2-5+deb12u1 is a security update, which bookworm's own list lacks).
  keyring=/usr/share/keyrings/debian-archive-keyring.gpg
  {
    echo "deb-src [signed-by=$keyring] http://deb.debian.org/debian bookworm main"
    echo "deb-src [signed-by=$keyring] http://deb.debian.org/debian bookworm-updates main"
    echo "deb-src [signed-by=$keyring] http://deb.debian.org/debian-security bookworm-security main"
  } > "$apt_dir/sources.list"
  apt_options=(-o Dir::Etc::SourceList="$apt_dir/sources.list" -o Dir::Etc::SourceParts=/nonexistent
               -o Dir::State::Lists="$apt_dir/lists" -o Dir::Cache="$apt_dir/cache"
               -o Debug::NoLocking=1 -o APT::Sandbox::User=root -qq)
  apt-get "${apt_options[@]}" update >&2
  if ! (cd "$build/zstd-package" && apt-get "${apt_options[@]}" source --download-only \
          "libzstd=$version" >/dev/null 2>&1); then
    # The installed version's source is not reachable (a security update whose source pool
    # this machine's mirror does not serve; apt's own errors for it are left out, the warning
    # below says it): the newest source of the same upstream release that is, said loudly,
    # since its decoder lacks the Debian patches after it.
    upstream=${version%-*}
    fallback=$(apt-cache "${apt_options[@]}" showsrc libzstd | awk '/^Version:/ {print $2}' |
               grep -F "$upstream-" | grep -vxF "$version" | sort -V | tail -n 1)
    if [[ -z "$fallback" ]]; then
      echo "web/build.sh: no source of libzstd $upstream is reachable (installed: $version)" >&2
      exit 1
    fi
    echo "web/build.sh: WARNING: libzstd $version's source is not reachable; the decoder is" \
         "built from libzstd $fallback's, without the Debian patches after it" >&2
    rm -f "$build/zstd-package"/*
    (cd "$build/zstd-package" && apt-get "${apt_options[@]}" source --download-only \
       "libzstd=$fallback" >&2)
  fi
  rm -rf "$zstd_src"
  dpkg-source --no-check -x "$build/zstd-package"/libzstd_*.dsc "$zstd_src" >/dev/null
fi

# -fexceptions: the interface catches what the library throws (bad_alloc above all). Debian's
# emscripten ships its C++ runtime prebuilt for JS-based exceptions (libc++-except), not for
# -fwasm-exceptions, and its cache is frozen; so JS-based ones.
emcmake cmake -S "$root" -B "$build/cmake" -DPM_CODEC_ONLY=ON -DCMAKE_BUILD_TYPE=Release \
  -DPM_ZSTD_TARGET=pm_zstd_decoder -DPM_ZSTD_SOURCE_DIR="$zstd_src" \
  -DCMAKE_CXX_FLAGS="-fexceptions" -DCMAKE_EXE_LINKER_FLAGS="-fexceptions" \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=ON -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON \
  -Wno-dev --no-warn-unused-cli >/dev/null
cmake --build "$build/cmake" -j"${PM_WEB_JOBS:-2}" --target pm_decoder
# dist/ is what a static server serves: the module, its worker and types, the viewer.
mkdir -p "$build/dist"
cp "$build/cmake/dist/pm_decoder.mjs" "$build/cmake/dist/pm_decoder.wasm" "$build/dist/"
cp "$root"/web/pm.js "$root"/web/pm-core.js "$root"/web/pm-worker.js "$root"/web/pm.d.ts \
   "$root"/web/pm-core.d.ts "$build/dist/"
# The viewer and three.js (npm, web/package-lock.json; .ci/deps runs npm ci, or here when missing).
if [[ ! -f "$root/web/node_modules/three/build/three.module.js" ]]; then
  (cd "$root/web" && npm ci --no-audit --no-fund >&2)
fi
three="$root/web/node_modules/three"
cp "$root"/web/viewer/index.html "$root"/web/viewer/viewer.js "$three"/build/three.module.js \
   "$three"/build/three.core.js "$three"/examples/jsm/controls/OrbitControls.js "$build/dist/"
