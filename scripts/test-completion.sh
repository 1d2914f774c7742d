#!/bin/bash
# Checks scripts/texsim-completion.bash against a built texsim: subcommands and options from
# its --help, the scene's keys after --set. Usage: test-completion.sh TEXSIM SOURCE_DIR
set -u
bin=$1
src=$2
# shellcheck source=scripts/texsim-completion.bash
source "$src/scripts/texsim-completion.bash"
comp() {
  COMP_WORDS=("$@")
  COMP_CWORD=$(($# - 1))
  COMPREPLY=()
  _texsim
  printf '%s\n' "${COMPREPLY[@]}" | LC_ALL=C sort
}
fail=0
expect() {  # expect NAME WANTED GOT
  if [[ $2 != "$3" ]]; then
    printf 'test-completion: %s: wanted\n%s\ngot\n%s\n' "$1" "$2" "$3"
    fail=1
  fi
}
expect subcommands "$(printf '%s\n' cosim import merge run study sweep trace tune)" "$(comp "$bin" "")"
expect "trace subcommands" "$(printf '%s\n' convert gen info)" "$(comp "$bin" trace "")"
expect "trace gen --se" "--set" "$(comp "$bin" trace gen --se)"
expect "run --time" "$(printf '%s\n' --timeline --timeline-limit)" "$(comp "$bin" run --time)"
expect "--set keys of the scene" \
  "$(printf '%s\n' materials.border_custom.filter= materials.border_custom.texture= materials.border_custom=)" \
  "$(comp "$bin" run "$src/scenes/border.toml" --set materials.border_c)"
expect "--set sections without a scene" "pipeline=" "$(comp "$bin" run --set pip)"
exit $fail
