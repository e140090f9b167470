# Shared settings for the tools/ scripts (sourced, not run).
BTI_CACHE=${BLOBTREE_INK_CACHE:-$HOME/.cache/blobtree-ink}
BTI_PYTHON=${BTI_PYTHON:-$(command -v python3.11 || command -v python3)}
BTI_BPY50_VERSION=5.0.1
BTI_BPY45_VERSION=4.5.15
BTI_VENV_CORE=$BTI_CACHE/venv-core
BTI_VENV_50=$BTI_CACHE/venv-bpy-$BTI_BPY50_VERSION
BTI_VENV_45=$BTI_CACHE/venv-bpy-$BTI_BPY45_VERSION
BTI_CHROOT=$BTI_CACHE/sid-chroot
BTI_REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
