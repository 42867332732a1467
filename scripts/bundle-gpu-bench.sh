#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# Packs bench_gpu and bench_controller with every shared library they need into gpu-bundle/
# (git-ignored), so that they run on a machine that has an NVIDIA GPU and its driver but none of
# our build dependencies.
# The GL/EGL loaders (glvnd) come from Debian's packages, unpacked into the bundle; the NVIDIA
# driver on the target supplies libEGL_nvidia through glvnd's vendor files.
#   scripts/bundle-gpu-bench.sh            # after scripts/build.sh
#   gpu-bundle/run.sh [bench_gpu args]     # on the GPU machine
#   gpu-bundle/run-controller.sh --backend gpu --bodies 1000   # bench_controller there
set -euo pipefail
cd "$(dirname "$0")/.."
rm -rf gpu-bundle && mkdir -p gpu-bundle/lib
for name in bench_gpu bench_controller; do
  bench="${BUILD_DIR:-build}/demos/$name"
  [ -x "$bench" ] || { echo "bundle-gpu-bench: $bench missing; run scripts/build.sh first" >&2; exit 1; }
  cp "$bench" gpu-bundle/
  # Every library ldd resolves, except the C runtime itself (the target's glibc loads ours).
  ldd "$bench" | awk '/=> \// {print $3}' | grep -vE '/(libc|libm|libdl|libpthread|librt|ld-linux[^/]*)\.so' |
    while read -r lib; do cp -L "$lib" gpu-bundle/lib/; done
done
# glvnd's loaders: libEGL.so.1, libOpenGL.so.0, libGLdispatch.so.0 (dlopened through libepoxy).
tmp=$(mktemp -d)
chmod 777 "$tmp"  # apt downloads as the _apt user
(cd "$tmp" && apt-get download libegl1 libglvnd0 libopengl0 >/dev/null)
for deb in "$tmp"/*.deb; do dpkg -x "$deb" "$tmp/root"; done
cp -L "$tmp"/root/usr/lib/x86_64-linux-gnu/lib{EGL.so.1,OpenGL.so.0,GLdispatch.so.0} gpu-bundle/lib/
rm -rf "$tmp"
cat > gpu-bundle/run.sh <<'RUN'
#!/usr/bin/env bash
# Runs the bundled bench_gpu against the machine's NVIDIA driver.
here="$(cd "$(dirname "$0")" && pwd)"
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$vendor" ] || vendor=/usr/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$vendor" ] && export __EGL_VENDOR_LIBRARY_FILENAMES="$vendor"
LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" exec "$here/bench_gpu" "$@"
RUN
sed 's|/bench_gpu"|/bench_controller"|; s|bench_gpu against|bench_controller against|' gpu-bundle/run.sh > gpu-bundle/run-controller.sh
chmod +x gpu-bundle/run.sh gpu-bundle/run-controller.sh
du -sh gpu-bundle
