#!/bin/sh
# Fails, naming them, when the shared object $1 links window code (GLFW, Dear ImGui, X11's GLX).
set -u
libraries=$(ldd "$1") || { echo "ldd $1 failed" >&2; exit 1; }
window=$(printf '%s\n' "$libraries" | grep -Ei 'glfw|imgui|libGLX' || true)
if [ -n "$window" ]; then
  echo "$1 links window code:" >&2
  printf '%s\n' "$window" >&2
  exit 1
fi
echo "$1 links no window code ($(printf '%s\n' "$libraries" | wc -l) libraries)"
