# Source this file to get the workspace and the venv in a shell:  source tools/env.sh
_pit_flags=$-
set +u   # ROS's setup scripts read unset variables
_pit_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$_pit_root/build/devel/setup.bash"
export PATH="$_pit_root/.venv/bin:$PATH"
export VIRTUAL_ENV="$_pit_root/.venv"
case $_pit_flags in *u*) set -u ;; esac
unset _pit_root _pit_flags
