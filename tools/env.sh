# Source this file to get the workspace and the venv in a shell:  source tools/env.sh
# With PEPPER_PLATFORM=noetic: the Noetic tier's Python 3.8 workspace and venv instead
# (build/noetic/, set up by tools/platform/noetic.sh).
_pit_flags=$-
set +u   # ROS's setup scripts read unset variables
_pit_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ "${PEPPER_PLATFORM:-}" = noetic ]; then
  _pit_ws="$_pit_root/build/noetic/ws"; _pit_venv="$_pit_root/build/noetic/venv"
else
  _pit_ws="$_pit_root/build"; _pit_venv="$_pit_root/.venv"
fi
source "$_pit_ws/devel/setup.bash"
export PATH="$_pit_venv/bin:$PATH"
export VIRTUAL_ENV="$_pit_venv"
case $_pit_flags in *u*) set -u ;; esac
unset _pit_root _pit_flags _pit_ws _pit_venv
