#!/usr/bin/env bash
# Captures frames of the game OpenArena (fixed-function OpenGL, ioquake3's opengl1 renderer)
# with apitrace under Xvfb on Mesa llvmpipe, with a scripted camera on a map, and writes the
# game's own images of chosen frames through glretrace. Everything comes from Debian; no
# display or GPU is needed.
#
# Usage: scripts/capture-openarena.sh [--map MAP] [--frames N] [--width W] [--height H]
#          [--viewpos "X Y Z YAW"] [--snap-frames LIST] [--out DIR] [--no-install]
#   --map        a map of /usr/lib/openarena/baseoa/pak1-maps.pk3 (default aggressor)
#   --frames     frames the game draws after the camera is placed (default 30); the capture
#                also holds the level load and the frames before the camera moved
#   --width/--height  window size (default 640x480)
#   --viewpos    camera position and yaw, set with `setviewpos` (default "200 -300 100 45")
#   --snap-frames  frames to image, "A-B" (0-based frame numbers of the capture; default the
#                last 5)
#   --out        output directory (default out/capture-MAP): MAP.trace (the capture),
#                frame_NNNN.png (glretrace's image of frame NNNN, the back buffer at its
#                glXSwapBuffers), capture.txt (the settings, frame count, sizes, times)
#   --no-install do not apt-get install the packages
#
# Measured on a 2-core AMD EPYC, x86-64 with AVX-512; packages already installed; `scripts/capture-openarena.sh
# --no-install --frames 30`, 640x480, aggressor): 4 s in all (game 2 s, 5 images 2 s); the
# capture holds 113 frames (the level load included) and is 13.7 MB. capture.txt of a run has
# its own figures.
# Known: the gauntlet may still be drawn at the bottom of the frame (cg_drawgun is set before
# and after the level loads).
#
# The game writes its config into $HOME, so every capture gets a fresh $HOME. The HUD, the
# weapon and the 2-D overlays are hidden (cg_draw2D 0, cg_drawgun 0), so the frames hold the
# world only. A camera placed with `setviewpos` needs cheats (a devmap). `r_clear 1` clears the
# colour buffer to (1, 0, 0.5) before each frame, so the images show which pixels the frame
# itself drew (without it the back buffer keeps earlier frames where the game draws nothing).
set -euo pipefail

map=aggressor
frames=30
width=640
height=480
viewpos="200 -300 100 45"
snap=""
out=""
install=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --map) map=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --width) width=$2; shift 2 ;;
    --height) height=$2; shift 2 ;;
    --viewpos) viewpos=$2; shift 2 ;;
    --snap-frames) snap=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --no-install) install=0; shift ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) echo "capture-openarena: unknown option '$1' (--help lists them)" >&2; exit 2 ;;
  esac
done
die() { echo "capture-openarena: $*" >&2; exit 2; }
[[ $map =~ ^[A-Za-z0-9_-]+$ ]] || die "--map '$map' is not a map name"
[[ $frames =~ ^[0-9]+$ ]] && ((frames >= 1 && frames <= 10000)) || die "--frames '$frames' is not in 1..10000"
[[ $width =~ ^[0-9]+$ ]] && ((width >= 64 && width <= 4096)) || die "--width '$width' is not in 64..4096"
[[ $height =~ ^[0-9]+$ ]] && ((height >= 64 && height <= 4096)) || die "--height '$height' is not in 64..4096"
read -r -a vp <<< "$viewpos"
[[ ${#vp[@]} -eq 4 ]] || die "--viewpos '$viewpos' is not four numbers X Y Z YAW"
for v in "${vp[@]}"; do [[ $v =~ ^-?[0-9]+(\.[0-9]+)?$ ]] || die "--viewpos value '$v' is not a number"; done
out=${out:-out/capture-$map}

if ((install)); then
  need=()
  for p in openarena apitrace apitrace-tracers xvfb xauth; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || need+=("$p")
  done
  if ((${#need[@]})); then
    sudo_cmd=(); [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
    "${sudo_cmd[@]}" apt-get update
    DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${need[@]}"
  fi
fi
pak=/usr/lib/openarena/baseoa/pak1-maps.pk3
if [[ -f $pak ]] && command -v unzip > /dev/null; then
  unzip -l "$pak" | grep -q "maps/$map.bsp" || die "map '$map' is not in $pak"
fi

mkdir -p "$out"
out=$(cd "$out" && pwd)
home=$(mktemp -d)
trap 'rm -rf "$home"' EXIT
export HOME=$home
mkdir -p "$HOME/.openarena/baseoa"
# The level loads during the first `wait`s; the camera is placed, then the game draws `frames`
# frames (one `wait` is one frame) and quits.
cat > "$HOME/.openarena/baseoa/cap.cfg" << EOF
set sv_cheats 1
set cg_draw2D 0
set cg_drawgun 0
set cg_drawCrosshair 0
set cg_drawFPS 0
set con_notifytime 0
wait 150
set cg_drawgun 0
set cg_draw2D 0
setviewpos ${vp[*]}
wait $frames
quit
EOF

trace=$out/$map.trace
rm -f "$trace"
start=$(date +%s)
xvfb-run -a -s "-screen 0 ${width}x${height}x24" apitrace trace -o "$trace" \
  /usr/games/openarena +set r_mode -1 +set r_customwidth "$width" +set r_customheight "$height" \
  +set r_fullscreen 0 +set s_initsound 0 +set cl_renderer opengl1 +set sv_pure 0 \
  +set cg_draw2D 0 +set cg_drawgun 0 +set r_clear 1 +devmap "$map" +exec cap.cfg > "$out/game.log" 2>&1 ||
  die "the game failed (see $out/game.log)"
[[ -s $trace ]] || die "no capture written (see $out/game.log)"
mid=$(date +%s)
total=$(apitrace info "$trace" | sed -n 's/.*"FramesCount": *\([0-9]*\).*/\1/p')
[[ -n $total ]] || total=$(apitrace dump --calls=frame "$trace" 2> /dev/null | grep -c . || true)
[[ $total =~ ^[0-9]+$ ]] && ((total >= 1)) || die "no frames in the capture"
if [[ -z $snap ]]; then snap="$((total > 5 ? total - 5 : 0))-$((total - 1))"; fi
[[ $snap =~ ^([0-9]+)-([0-9]+)$ ]] || die "--snap-frames '$snap' is not A-B"
a=${BASH_REMATCH[1]} b=${BASH_REMATCH[2]}
((a <= b && b < total)) || die "--snap-frames '$snap' is outside 0-$((total - 1))"
# glretrace takes call numbers: the frame-ending calls (glXSwapBuffers) of frames a..b.
mapfile -t swaps < <(apitrace dump --calls=frame --arg-names=no "$trace" | sed -n 's/^\([0-9][0-9]*\) .*/\1/p')
((${#swaps[@]} >= b + 1)) || die "the capture lists ${#swaps[@]} frame ends, fewer than $((b + 1))"
rm -f "$out"/snap_*.png "$out"/frame_*.png
(cd "$out" && xvfb-run -a -s "-screen 0 ${width}x${height}x24" glretrace \
  --snapshot-force-backbuffer --snapshot="${swaps[a]}-${swaps[b]}/frame" --snapshot-prefix=snap_ \
  "$trace" > retrace.log 2>&1) || die "glretrace failed (see $out/retrace.log)"
for ((f = a; f <= b; ++f)); do
  img=$(printf '%s/snap_%010d.png' "$out" "${swaps[f]}")
  [[ -f $img ]] || die "glretrace wrote no image of frame $f (call ${swaps[f]}; see $out/retrace.log)"
  mv "$img" "$(printf '%s/frame_%04d.png' "$out" "$f")"
done
end=$(date +%s)
{
  echo "map $map, ${width}x${height}, viewpos ${vp[*]}, $frames frames after the camera"
  echo "capture $trace: $(stat -c %s "$trace") bytes, $total frames, $((mid - start)) s"
  echo "images of frames $a-$b (frame_NNNN.png): $((end - mid)) s"
} | tee "$out/capture.txt"
