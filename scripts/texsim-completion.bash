# bash completion for texsim (installed as share/bash-completion/completions/texsim).
# Subcommands and options come from texsim's own --help (about 16 ms a call, so they follow the
# binary); after --set, the keys come from the scene file on the command line: its tables and
# keys as dotted paths (materials.floor.filter, pipeline.units, ...), then the sections every
# scene may have.

_texsim_help_words() {
  # $1: the section of --help to read ("Subcommands" or "Options"), the rest: the command path.
  local section=$1
  shift
  "$_texsim_bin" "$@" --help 2>/dev/null | awk -v s="$section:" '
    $0 ~ "^" s { on = 1; next }
    /^[A-Z][a-z]*:/ { on = 0 }
    on && s == "Subcommands:" && /^  [a-z]/ { print $1 }
    on && s == "Options:" && /^  -/ {
      n = split($1, f, ",")
      for (i = 1; i <= n; ++i) if (f[i] ~ /^--?[a-z]/) { sub(/\{.*/, "", f[i]); print f[i] }
    }'
}

_texsim_scene_keys() {
  # Dotted keys of a TOML scene: "[a.b]" tables and "key = " lines inside them (inline tables'
  # own keys are not listed: --set replaces the whole value).
  [[ -r $1 ]] || return
  awk '
    /^[ \t]*\[\[/ { t = ""; next }
    /^[ \t]*\[/ { t = $0; gsub(/[][ \t]/, "", t); print t; next }
    /^[ \t]*[A-Za-z0-9_]+[ \t]*=/ { k = $0; sub(/[ \t]*=.*/, "", k); gsub(/[ \t]/, "", k)
      print (t == "" ? k : t "." k) }' "$1"
}

_texsim() {
  local cur prev words cword
  _init_completion -n = 2>/dev/null || {
    cur=${COMP_WORDS[COMP_CWORD]}
    prev=${COMP_WORDS[COMP_CWORD - 1]}
    words=("${COMP_WORDS[@]}")
    cword=$COMP_CWORD
  }
  _texsim_bin=${words[0]}
  # The command path so far (texsim trace gen ...) and a scene file, if one was named.
  local path=() scene="" i w subs
  for ((i = 1; i < cword; ++i)); do
    w=${words[i]}
    [[ $w == *.toml ]] && scene=$w
    if [[ $w != -* ]] && subs=$(_texsim_help_words Subcommands "${path[@]}") &&
      [[ $'\n'$subs$'\n' == *$'\n'$w$'\n'* ]]; then
      path+=("$w")
    fi
  done
  if [[ $prev == --set ]]; then
    local keys
    keys=$(
      _texsim_scene_keys "$scene"
      printf '%s\n' output camera pipeline reference raster lighting textures materials
    )
    compopt -o nospace 2>/dev/null
    mapfile -t COMPREPLY < <(compgen -W "$keys" -S = -- "$cur")
    return
  fi
  case $prev in
    --out | -o) mapfile -t COMPREPLY < <(compgen -d -- "$cur") && return ;;
    --trace | --draws | --timeline | --ledger-maps) mapfile -t COMPREPLY < <(compgen -f -- "$cur") && return ;;
  esac
  if [[ $cur == -* ]]; then
    mapfile -t COMPREPLY < <(compgen -W "$(_texsim_help_words Options "${path[@]}")" -- "$cur")
    return
  fi
  subs=$(_texsim_help_words Subcommands "${path[@]}")
  if [[ -n $subs ]]; then
    mapfile -t COMPREPLY < <(compgen -W "$subs" -- "$cur")
  else
    mapfile -t COMPREPLY < <(compgen -f -X '!*.@(toml|trc|csv|draws)' -- "$cur"; compgen -d -- "$cur")
  fi
}
complete -F _texsim texsim
