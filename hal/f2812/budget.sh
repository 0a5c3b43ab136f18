#!/usr/bin/env bash
# budget.sh - code/data size of the F2812 image's control path, measured on the proxy cross builds
# (cross-cm0: arm-none-eabi, Thumb; cross-avr: avr-gcc), and whether the ISR path fits the
# zero-wait RAM the linker command files reserve for it (section "ramfuncs").
#
#   usage: hal/f2812/budget.sh PROJECT_ROOT     (after: cmake --build --preset cross-cm0 / cross-avr)
#              the PM image (dtc_f2812: the application of the build's DTC_LAWS, pm in the presets)
#              with its placement, linker/f2812_flash.cmd
#          hal/f2812/budget.sh PROJECT_ROOT --im [CM0_BUILD_DIR]
#              the IM image (dtc_f2812_im: the IM-only application libdtc_app_im.a,
#              libdtc_proto_im.a and f2812_main_im that the cross-cm0 preset builds beside the PM
#              image's, default build/cross-cm0; or a cross-cm0 build with -DDTC_LAWS=im, whose
#              libdtc_app.a is the IM application) with its placement, linker/f2812_flash_im.cmd;
#              cross-cm0 only
#          hal/f2812/budget.sh PROJECT_ROOT --members [CM0_BUILD_DIR]
#              only the firmware archives' members each image of that build links, one line per
#              archive, and the law check below.
#
# Which law's code an image links: the PM image links no member of the IM law (im_*, dsc, dsvm)
# and the IM image none of the PM laws (dtc, flux_est, itc*, dqpi, svm4, dtc_init, dtc_reconfig,
# dtc_check); a member of the other law fails the check (a call across the laws pulls it in).
#
# What is counted
#   firmware   the members of libdtc_firmware.a, libdtc_fixmath.a, libdtc_im.a and the
#              application's archive that the image links (those f2812_main.c and the HAL
#              reference, directly or not: a linker pulls only referenced archive members, so a
#              control law the application does not call is not in the image). The flash images'
#              .cmd files place the functions they name (the ISR's hot path, hal/f2812/
#              hot_functions.py) in zero-wait RAM, ramfuncs (L0+L1), ramfuncs_h (H0's first 6.5K
#              words) and ramfuncs_m (M1), with every control table in ramfuncs; the rest of these
#              archives runs from flash. libdtc_config.a, libdtc_init.a, the application's _init and
#              _flash archives (the configuration's validation, the laws' init, the application's
#              init and background calls, the parameters by id, the commissioning and the
#              calibration's rotor hold, which run in place of the law) stay in flash. The members
#              are found by a relocatable link of the proxy objects (ld -r -M). The blocks' sizes
#              come from linker/f2812_flash_mem.cmd. The RAM build (linker/f2812_ram.cmd, PM only)
#              places whole archives: reported, not checked.
#   hal        libhal_f2812.a without the register blocks (RAM on the proxies, peripheral frames on
#              the DSP); the ISR-path part is the functions marked F2812_RAMFUNC in hal/f2812/*.c
#              and target/f2812/*.c.
#   main       target/f2812/f2812_main.c (main and the ADCINT glue; the glue is a ramfunc).
#
# ESTIMATE, clearly: no C28x compiler is available here. C28x and Thumb both have 16-bit base
# encodings with 32-bit forms; the C28x does 32-bit multiplies/shifts/saturation in one
# instruction where Thumb-1 needs several, but uses 32-bit forms more often. We therefore take
#     C28x code words ~= Thumb bytes / 2          (nominal)
#     C28x code words <= Thumb bytes / 2 * 1.5    (pessimistic, used for the pass/fail check)
# and for data: words = bytes / 2 (16-bit and 32-bit types have the same word counts on both;
# the C28x has no 8-bit type). AVR figures are printed for information only (8-bit code is not
# comparable). The real figures come from the map file of the f2812 preset (cl2000).
set -euo pipefail
export LC_ALL=C   # sort and join agree on the order
root=${1:?usage: budget.sh PROJECT_ROOT [--members [CM0_BUILD_DIR]]}
# Archive members of one law only (the linked member lists below are checked against them).
PM_ONLY='dtc|flux_est|itc|itc_check|dqpi|svm4|dtc_init|dtc_reconfig|dtc_check'
IM_ONLY='im_[a-z_]*|dsc|dsvm'
# law_members LABEL DIR APP MAINDIR: the archive members an image links (cross-cm0 ld -r -M), one line
# per archive, and the check that they hold no code of the other laws (status 1 if they do).
law_members() {
  local label=$1 dir=$2 app_ar=$3 main=$2/target/f2812/CMakeFiles/$4/f2812_main.c.obj map a list bad
  [ -f "$main" ] || { echo "budget: no $main" >&2; exit 2; }
  echo "== archive members linked by the $label image of $dir, cross-cm0 ld -r -M"
  map=$(arm-none-eabi-ld -r -M -o /dev/null "$main" --start-group "$dir/hal/f2812/libhal_f2812.a" \
          "$dir/firmware/$app_ar.a" "$dir/firmware/${app_ar}_init.a" "$dir/firmware/libdtc_init.a" \
          "$dir/firmware/libdtc_im.a" "$dir/firmware/libdtc_firmware.a" "$dir/firmware/libdtc_config.a" \
          "$dir/firmware/libdtc_fixmath.a" --end-group 2>/dev/null)
  for a in "$app_ar" libdtc_firmware libdtc_im libdtc_init libdtc_config libdtc_fixmath; do
    list=$(printf '%s\n' "$map" | grep -o "$a\\.a([A-Za-z0-9_.]*)" | sed 's/.*(\(.*\))/\1/; s/\.c\.obj$//' | sort -u)
    printf '  %-17s %s\n' "$a.a:" "$(printf '%s\n' "$list" | paste -sd' ')"
    [ "$label" = PM ] && bad=$IM_ONLY || bad=$PM_ONLY
    if printf '%s\n' "$list" | grep -qxE "$bad"; then
      echo "budget: the $label image links code of another law: $(printf '%s\n' "$list" | grep -xE "$bad" | paste -sd' ')" >&2
      return 1
    fi
  done
}
if [ "${2:-}" = --members ]; then
  dir=${3:-$root/build/cross-cm0}
  laws=$(sed -n 's/^DTC_LAWS:STRING=//p' "$dir/CMakeCache.txt")
  rc=0
  case "$laws" in
    pm) law_members PM "$dir" libdtc_app f2812_main.dir || rc=1 ;;
    im) law_members IM "$dir" libdtc_app f2812_main.dir || rc=1 ;;
    *)  echo "budget: DTC_LAWS=$laws links several laws: no law check"; law_members ALL "$dir" libdtc_app f2812_main.dir || true ;;
  esac
  if [ -f "$dir/firmware/libdtc_app_im.a" ]; then
    law_members IM "$dir" libdtc_app_im f2812_main_im.dir || rc=1
  fi
  exit $rc
fi
cm0=$root/build/cross-cm0
avr=$root/build/cross-avr
image=pm
app=libdtc_app       # the image's application archives: $app.a, ${app}_init.a; and $proto.a
proto=libdtc_proto
main_dir=f2812_main.dir   # the image's main object: target/f2812/CMakeFiles/$main_dir/
if [ "${2:-}" = --im ]; then
  image=im
  cm0=${3:-$root/build/cross-cm0}
  avr=
  layout_sfx=_im
  if [ -f "$cm0/firmware/libdtc_app_im.a" ]; then
    app=libdtc_app_im; proto=libdtc_proto_im; main_dir=f2812_main_im.dir
  fi
fi

# Zero-wait RAM reserved for ramfuncs (linker/f2812_flash.cmd: L0+L1; linker/f2812_ram.cmd: H0
# after the 2-word boot entry).
RAMFUNCS_FLASH_WORDS=8192
RAMFUNCS_RAM_WORDS=8190
# ramfuncs_h (the fixed-point core and the application): H0's first 7K words (flash build), L1 (RAM build).
RAMFUNCS_H_FLASH_WORDS=7168
RAMFUNCS_H_RAM_WORDS=4096

need() { [ -f "$1" ] || { echo "budget: $1 not found (build the cross presets first)" >&2; exit 2; }; }
for d in "$cm0" ${avr:+"$avr"}; do
  for f in "$d/firmware/libdtc_firmware.a" "$d/firmware/libdtc_fixmath.a" "$d/firmware/$app.a" \
           "$d/firmware/libdtc_im.a" "$d/firmware/libdtc_config.a" "$d/firmware/libdtc_init.a" \
           "$d/hal/f2812/libhal_f2812.a"; do
    need "$f"
  done
done
cm0_main=$cm0/target/f2812/CMakeFiles/$main_dir/f2812_main.c.obj
need "$cm0_main"
if [ -n "$avr" ]; then
  avr_main=$avr/target/f2812/CMakeFiles/f2812_main.dir/f2812_main.c.obj
  need "$avr_main"
fi

# Sum sections of `size -A` output by kind: text / rodata / data / bss.
sum_sections() { # $1 = size tool, rest = files
  local tool=$1; shift
  [ $# -gt 0 ] || { echo "0 0 0 0"; return; }
  "$tool" -A "$@" | awk '
    $1 ~ /^\.text/   { t += $2 } $1 ~ /^\.rodata/ { r += $2 }
    $1 ~ /^\.data/   { d += $2 } $1 ~ /^\.bss/    { b += $2 }
    END { printf "%d %d %d %d\n", t, r, d, b }'
}
# Sizes (bytes) of the named symbols in the given files.
sum_symbols() { # $1 = nm tool, $2 = regex of names, rest = files
  local tool=$1 re=$2; shift 2
  "$tool" -S -t d "$@" 2>/dev/null | awk -v re="^(${re})$" 'NF == 4 && $4 ~ re { s += $2 } END { print s + 0 }'
}

# Bytes of the register blocks and the host CPU emulation, by kind (data, bss): RAM on the proxies,
# peripheral frames (not RAM) on the DSP, so they are subtracted.
REGS='f2812_(flash|piectrl|pievect|sysctrl|gpiomux|adc|eva|spia|scia|host_cpu)'
reg_bytes() { # $1 = nm tool, $2 = file; prints "data bss"
  "$1" -S -t d "$2" 2>/dev/null | awk -v re="^${REGS}$" '
    NF == 4 && $4 ~ re { if ($3 ~ /[Dd]/) d += $2; else if ($3 ~ /[BbCc]/) b += $2 }
    END { printf "%d %d\n", d, b }'
}

ramfuncs=$(grep -ho 'F2812_RAMFUNC([a-z0-9_]*)' "$root"/hal/f2812/*.c "$root"/target/f2812/*.c | sed 's/.*(\(.*\))/\1/' | sort -u | paste -sd'|')

# The firmware archive's members that a link of main + HAL pulls in, extracted into $tmp/<label>.
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
linked_members() { # $1 = label, $2 = ld tool, $3 = build dir, $4 = main obj, $5 = archive name,
                  # $6 = "optional": no member linked is not an error
  local dir="$tmp/$1/$5" ar_tool=${2%ld}ar members
  mkdir -p "$dir"
  members=$("$2" -r -M -o "$dir/all.o" "$4" --start-group "$3/hal/f2812/libhal_f2812.a" \
              "$3/firmware/$app.a" "$3/firmware/${app}_init.a" \
              "$3/firmware/libdtc_init.a" "$3/firmware/libdtc_im.a" \
              "$3/firmware/libdtc_firmware.a" \
              "$3/firmware/libdtc_config.a" "$3/firmware/libdtc_fixmath.a" \
              "$3/firmware/$proto.a" "$3/firmware/libdtc_comm.a" \
              --end-group 2>/dev/null |
            grep -o "$5\\.a([A-Za-z0-9_.]*)" | sed 's/.*(\(.*\))/\1/' | sort -u)
  if [ -z "$members" ]; then
    [ "${6:-}" = optional ] && return 0
    echo "budget: no $5 member linked for $1" >&2; exit 2
  fi
  local archive; archive=$(realpath "$3/firmware/$5.a")
  (cd "$dir" && "$ar_tool" x "$archive" $members)
  for m in $members; do echo "$dir/$m"; done
}
report() { # $1 = label, $2 = size tool, $3 = nm tool, $4 = build dir, $5 = main obj, $6 = ld tool
  local fw_list fx_list app_list im_list cf_list
  fw_list=$(linked_members "$1" "$6" "$4" "$5" libdtc_firmware) || exit 2
  fx_list=$(linked_members "$1" "$6" "$4" "$5" libdtc_fixmath) || exit 2
  app_list=$(linked_members "$1" "$6" "$4" "$5" "$app") || exit 2
  im_list=$(linked_members "$1" "$6" "$4" "$5" libdtc_im optional) || exit 2
  cf_list=$(linked_members "$1" "$6" "$4" "$5" libdtc_config) || exit 2
  in_list=$(linked_members "$1" "$6" "$4" "$5" libdtc_init optional) || exit 2
  ai_list=$(linked_members "$1" "$6" "$4" "$5" "${app}_init" optional) || exit 2
  pr_list=$(linked_members "$1" "$6" "$4" "$5" "$proto" optional) || exit 2
  cm_list=$(linked_members "$1" "$6" "$4" "$5" libdtc_comm optional) || exit 2
  # The operation layer: the ISR's part of libdtc_comm.a (capture.c, faultlog.c: run while a
  # capture records and at a fault; the flash images' .cmd place their ISR functions by name in
  # ramfuncs, the rest in flash) and the background's, in flash (the frames, the store, the
  # dispatcher and the application's background operations, libdtc_proto.a).
  mapfile -t ci_objs < <(printf '%s\n' "$cm_list" | grep -E '/(capture|faultlog)\.c\.(o|obj)$')
  mapfile -t op_objs < <(printf '%s\n%s\n' "$pr_list" "$cm_list" | sed '/^$/d' | grep -vE '/(capture|faultlog)\.c\.(o|obj)$')
  mapfile -t fw_objs <<< "$fw_list"
  mapfile -t fx_objs < <(printf '%s\n%s\n' "$fx_list" "$app_list")
  mapfile -t im_objs < <(printf '%s' "$im_list" | sed '/^$/d')
  mapfile -t cf_objs < <(printf '%s\n%s\n%s\n' "$cf_list" "$in_list" "$ai_list" | sed '/^$/d')
  read -r fw_t fw_r fw_d fw_b < <(sum_sections "$2" "${fw_objs[@]}")
  read -r fx_t fx_r fx_d fx_b < <(sum_sections "$2" "${fx_objs[@]}")
  read -r im_t im_r im_d im_b < <(sum_sections "$2" "${im_objs[@]}")
  read -r cf_t cf_r cf_d cf_b < <(sum_sections "$2" "${cf_objs[@]}")
  read -r op_t op_r op_d op_b < <(sum_sections "$2" "${op_objs[@]}")
  read -r ci_t ci_r ci_d ci_b < <(sum_sections "$2" "${ci_objs[@]}")
  op_data=$((op_d + op_b + ci_d + ci_b))
  fx_t=$((fx_t + im_t)); fx_r=$((fx_r + im_r)); fx_d=$((fx_d + im_d)); fx_b=$((fx_b + im_b))
  read -r hal_t hal_r hal_d hal_b < <(sum_sections "$2" "$4/hal/f2812/libhal_f2812.a")
  read -r reg_d reg_b < <(reg_bytes "$3" "$4/hal/f2812/libhal_f2812.a")
  hal_d=$((hal_d - reg_d)); hal_b=$((hal_b - reg_b))
  read -r mn_t mn_r mn_d mn_b < <(sum_sections "$2" "$5")
  hal_isr=$(sum_symbols "$3" "$ramfuncs" "$4/hal/f2812/libhal_f2812.a" "$5")
  printf '%-9s %-28s %8s %8s %8s %8s\n' "$1" "bytes" ".text" ".rodata" ".data" ".bss"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "libdtc_firmware.a (linked)" "$fw_t" "$fw_r" "$fw_d" "$fw_b"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "libdtc_im.a (linked)" "$im_t" "$im_r" "$im_d" "$im_b"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "fixmath + app + im (linked)" "$fx_t" "$fx_r" "$fx_d" "$fx_b"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "config + inits (flash)" "$cf_t" "$cf_r" "$cf_d" "$cf_b"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "capture + log (ISR part)" "$ci_t" "$ci_r" "$ci_d" "$ci_b"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "proto + comm (flash)" "$op_t" "$op_r" "$op_d" "$op_b"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "libhal_f2812.a (no regs)" "$hal_t" "$hal_r" "$hal_d" "$hal_b"
  printf '%-9s %-28s %8d %8d %8d %8d\n' "" "f2812_main.c" "$mn_t" "$mn_r" "$mn_d" "$mn_b"
  printf '%-9s %-28s %8d\n' "" "hal ISR-path functions" "$hal_isr"
}

echo "== F2812 control-path size budget, $image image (proxy builds; see the ESTIMATE note in this script) =="
echo "hal ramfuncs: ${ramfuncs//|/ }"
report cross-cm0 arm-none-eabi-size arm-none-eabi-nm "$cm0" "$cm0_main" arm-none-eabi-ld
# The RAM build (linker/f2812_ram.cmd, PM image only, a debugging image) places by archive:
# libdtc_firmware.a in H0, the fixed-point core and the application in L1.
ramb_l_pess=$(( (fw_t + hal_isr) * 3 / 4 + (fw_r + 1) / 2 ))
ramb_h_pess=$(( fx_t * 3 / 4 + (fx_r + 1) / 2 ))
# The flash build places by function (linker/f2812_flash.cmd, PM image; f2812_flash_im.cmd, IM
# image; cl2000 --gen_func_subsections): the functions the file names in ramfuncs (L0+L1),
# ramfuncs_h (H0's first part) and ramfuncs_m (M1) run from zero-wait RAM, the rest of the control
# archives' code from flash; every control archive's tables (.econst) in ramfuncs. A function's
# size is its symbol's on the proxy (gcc's clones, NAME.constprop.N and the like, counted as
# NAME); a name the file lists that the image does not define (renamed, or inlined by gcc) is an
# error: the lists are kept to the code (hal/f2812/hot_functions.py writes them).
cmd=$root/linker/f2812_flash${layout_sfx:-}.cmd
need "$cmd"
mem=$root/linker/f2812_flash_mem.cmd   # the flash images' memory map
need "$mem"
cmd_text=$(perl -0pe 's{/\*.*?\*/}{}gs' "$cmd")
mem_text=$(perl -0pe 's{/\*.*?\*/}{}gs' "$mem")
mem_len() { # length in words of the MEMORY block $1
  printf '%d\n' "$(printf '%s\n' "$mem_text" | sed -n "s/^ *$1 *: *origin *= *0x[0-9A-Fa-f]*, *length *= *\(0x[0-9A-Fa-f]*\).*/\1/p")"
}
sect_funcs() { # the function names section $1 of the .cmd places by name
  printf '%s\n' "$cmd_text" | awk -v sec="$1" '
    $0 ~ "^[ \t]*" sec "[ \t]*:" { on = 1 }
    on { while (match($0, /\.text:_[A-Za-z0-9_]+/)) { print substr($0, RSTART + 7, RLENGTH - 7); $0 = substr($0, RSTART + RLENGTH) } }
    on && /}/ { on = 0 }' | sort -u
}
RAMFUNCS_FLASH_WORDS=$(mem_len RAML0L1)
RAMFUNCS_H_FLASH_WORDS=$(mem_len RAMH0P)
EBSS_WORDS=$(mem_len RAMH0D)
fn_sizes() { # name and bytes of the functions of the given objects, sorted by name
  arm-none-eabi-nm -S -t d "$@" 2>/dev/null |
    awk 'NF == 4 && $3 ~ /^[tT]$/ { n = $4; sub(/\..*/, "", n); s[n] += $2 } END { for (n in s) print n, s[n] }' | sort
}
fn_sizes "${fw_objs[@]}" "${fx_objs[@]}" "${im_objs[@]}" "${ci_objs[@]}" >"$tmp/funcs"
# the operation layer's ISR part (capture.c, faultlog.c of libdtc_comm.a): the .cmd places it by name
# (hal/f2812/hot_functions.py OPS_ISR), outside the control archives' code counted above
if [ ${#ci_objs[@]} -gt 0 ]; then fn_sizes "${ci_objs[@]}" >"$tmp/ci_funcs"; else : >"$tmp/ci_funcs"; fi
place_bytes() { # bytes of the functions section $1 names; exits on a name the image lacks
  # An empty list is 0 bytes: hot_functions.py leaves M1 empty when H0 and L0+L1 hold every hot
  # function within the image's fill (its copy then moves 0 words, load start = load end).
  local names; names=$(sect_funcs "$1")
  [ -n "$names" ] || { echo 0; return; }
  local missing; missing=$(printf '%s\n' "$names" | join -v1 - "$tmp/funcs")
  [ -z "$missing" ] || { echo "budget: $cmd names functions the $image image does not define: $(echo $missing) (hal/f2812/hot_functions.py --image $image --write)" >&2; exit 2; }
  printf '%s\n' "$names" | join - "$tmp/funcs" | awk '{ s += $2 } END { print s + 0 }'
}
RAMFUNCS_M_WORDS=$(mem_len RAMM1P)
ram_l_bytes=$(place_bytes ramfuncs)
ram_h_bytes=$(place_bytes ramfuncs_h)
ram_m_bytes=$(place_bytes ramfuncs_m)
dup=$(sect_funcs ramfuncs; sect_funcs ramfuncs_h; sect_funcs ramfuncs_m)
dup=$(printf '%s\n' "$dup" | sort | uniq -d)
[ -z "$dup" ] || { echo "budget: $cmd places functions in two sections: $(echo $dup)" >&2; exit 2; }
ci_ram_bytes=$( { sect_funcs ramfuncs; sect_funcs ramfuncs_h; sect_funcs ramfuncs_m; } | sort -u |
  join - "$tmp/ci_funcs" | awk '{ s += $2 } END { print s + 0 }')
flash_code_bytes=$((fw_t + fx_t + ci_ram_bytes - ram_l_bytes - ram_h_bytes - ram_m_bytes))
isr_code_bytes=$((ram_l_bytes + hal_isr))
isr_table_bytes=$((fw_r + fx_r))
fx_code_bytes=$ram_h_bytes
fx_table_bytes=0
state_bytes=$((fw_d + fw_b + fx_d + fx_b + cf_d + cf_b + hal_d + hal_b + mn_d + mn_b))
op_code_bytes=$((op_t + ci_t - ci_ram_bytes))
op_data_bytes=$op_data
[ -z "$avr" ] || report cross-avr avr-size avr-nm "$avr" "$avr_main" avr-ld

words_nom() { echo $(( ($1 + 1) / 2 )); }
words_pess() { echo $(( ($1 * 3 + 3) / 4 )); }
pct() { echo $((100 * $1 / $2)); }
nom=$(words_nom "$isr_code_bytes"); pess=$(words_pess "$isr_code_bytes"); tables=$(words_nom "$isr_table_bytes")
fx_nom=$(words_nom "$fx_code_bytes"); fx_pess=$(words_pess "$fx_code_bytes"); fx_tables=$(words_nom "$fx_table_bytes")
state=$(words_nom "$state_bytes")
total_pess=$((pess + tables))
fx_total_pess=$((fx_pess + fx_tables))
# A block is full at 95 % of its words: the estimate keeps 5 % for what it cannot see (cl2000's
# inlining and its own helpers).
MARGIN_PCT=95
fits() { [ $(($1 * 100)) -le $(($2 * MARGIN_PCT)) ]; } # $1 words in a block of $2 words, with the margin
echo
echo "ISR path in zero-wait RAM (from cross-cm0; C28x 16-bit words, ESTIMATE):"
printf '  ramfuncs   the hot functions %s names for L0+L1 and the HAL ramfuncs: code %6d words nominal, %6d pessimistic; all control tables %d words\n' \
  "${cmd#$root/}" "$nom" "$pess" "$tables"
printf '             pessimistic total %d words: flash build L0+L1 %d words (%d%%)\n' \
  "$total_pess" "$RAMFUNCS_FLASH_WORDS" "$(pct "$total_pess" "$RAMFUNCS_FLASH_WORDS")"
printf '  ramfuncs_h the hot functions it names for H0: code %6d words nominal, %6d pessimistic\n' "$fx_nom" "$fx_pess"
printf '             pessimistic total %d words: flash build H0 (first part) %d words (%d%%)\n' \
  "$fx_total_pess" "$RAMFUNCS_H_FLASH_WORDS" "$(pct "$fx_total_pess" "$RAMFUNCS_H_FLASH_WORDS")"
m_pess=$(words_pess "$ram_m_bytes")
printf '  ramfuncs_m the hot functions it names for M1: code %6d words nominal, %6d pessimistic: M1 %d words (%d%%)\n' \
  "$(words_nom "$ram_m_bytes")" "$m_pess" "$RAMFUNCS_M_WORDS" "$(pct "$m_pess" "$RAMFUNCS_M_WORDS")"
printf '  flash      the rest of the control code: %6d words nominal, %6d pessimistic (start-up, rare\n' \
  "$(words_nom "$flash_code_bytes")" "$(words_pess "$flash_code_bytes")"
printf '             paths; its wait states per ISR: tools/pil/pil_profile.py --ram-cmd %s)\n' "${cmd#$root/}"
printf '  state      %6d words (.ebss: H0 RAMH0D, %d words, %d%%)\n' "$state" "$EBSS_WORDS" "$(pct "$state" "$EBSS_WORDS")"
if [ "$image" = pm ]; then
  printf '  RAM build  (linker/f2812_ram.cmd, by archive, debugging image) H0 %d of %d words (%d%%), L1 %d of %d words (%d%%)\n' \
    "$ramb_l_pess" "$RAMFUNCS_RAM_WORDS" "$(pct "$ramb_l_pess" "$RAMFUNCS_RAM_WORDS")" \
    "$ramb_h_pess" "$RAMFUNCS_H_RAM_WORDS" "$(pct "$ramb_h_pess" "$RAMFUNCS_H_RAM_WORDS")"
fi
layout=$cmd
# The operation layer (docs/operate.md): its code in flash but the ISR's part (the capture's
# recording and the fault log's record, placed by name in zero-wait RAM: the frames, the parameter
# store, the dispatcher and the application's background operations), its data (the
# capture buffer of CAPTURE_BUF_WORDS32 int32 values, the fault log, the frame decoder's ring, the
# dispatcher's frames, the stored-set buffer and the configuration copy a parameter write is
# checked on) in the section opdata, which the flash build's .cmd places in external RAM on XINTF
# zone 6 (XRAM, 64K words: a board fact, unverified), outside the zero-wait RAM of the ISR path.
cap_words=$(( 2 * $(sed -n 's/^#define CAPTURE_BUF_WORDS32 \([0-9]*\)u$/\1/p' "$root/firmware/comm/capture.h") ))
h0_free=$((RAMFUNCS_H_FLASH_WORDS - fx_total_pess))
ebss_free=$((EBSS_WORDS - state))
op_data=$(words_nom "$op_data_bytes")
xram_words=$(mem_len XRAM)
grep -q -- "-l=libdtc_proto${layout_sfx:-}.a (.ebss)" "$layout" &&
  grep -q -- '-l=libdtc_comm.a (.ebss)' "$layout" ||
  { echo "budget: ${layout#$root/} does not place the operation layer's .ebss in opdata" >&2; exit 2; }
echo
echo "Operation layer (cross-cm0, ESTIMATE):"
printf '  code       %6d words nominal, %6d pessimistic in flash (capture and log setup and read-out, frames, store, dispatcher)\n' \
  "$(words_nom "$op_code_bytes")" "$(words_pess "$op_code_bytes")"
ci_names=$(cut -d' ' -f1 "$tmp/ci_funcs" | grep -xF -f <({ sect_funcs ramfuncs; sect_funcs ramfuncs_h; sect_funcs ramfuncs_m; }) | paste -sd' ' || true)
printf '  ISR part   %6d words nominal, %6d pessimistic in zero-wait RAM (%s)\n' \
  "$(words_nom "$ci_ram_bytes")" "$(words_pess "$ci_ram_bytes")" "${ci_names:-none named: the ISR part runs from flash}${ci_names:+; counted in its block above}"
printf '  opdata     %6d words, of them %d the capture buffer (CAPTURE_BUF_WORDS32 int32): XRAM (XINTF zone 6) %d words (%d%%)\n' \
  "$op_data" "$cap_words" "$xram_words" "$(pct "$op_data" "$xram_words")"
printf '             zero-wait RAM left beside the image: H0 after ramfuncs_h %d words (pessimistic), .ebss %d words\n' \
  "$h0_free" "$ebss_free"
status=0
# The flash build is the product and must fit, each block with the margin. The RAM build is a
# debugging image (linker/f2812_ram.cmd, PM image only): with both control laws linked its
# pessimistic total exceeds L1 (4K words) for ramfuncs_h; that is reported, not failed
# (docs/f2812.md, "RAM build").
if ! fits "$total_pess" "$RAMFUNCS_FLASH_WORDS"; then
  echo "budget: the ISR path (pessimistic estimate) does NOT fit ${MARGIN_PCT} % of L0+L1 in the flash build" >&2
  status=1
fi
if ! fits "$fx_total_pess" "$RAMFUNCS_H_FLASH_WORDS"; then
  echo "budget: ramfuncs_h (pessimistic estimate) does NOT fit ${MARGIN_PCT} % of its part of H0 in the flash build" >&2
  status=1
fi
if ! fits "$m_pess" "$RAMFUNCS_M_WORDS"; then
  echo "budget: ramfuncs_m (pessimistic estimate) does NOT fit ${MARGIN_PCT} % of M1" >&2
  status=1
fi
if [ "$image" = pm ] && { [ "$ramb_l_pess" -gt "$RAMFUNCS_RAM_WORDS" ] || [ "$ramb_h_pess" -gt "$RAMFUNCS_H_RAM_WORDS" ]; }; then
  echo "budget: WARNING: the RAM build (debug image) does NOT fit by the pessimistic estimate (H0 $ramb_l_pess of $RAMFUNCS_RAM_WORDS, L1 $ramb_h_pess of $RAMFUNCS_H_RAM_WORDS words)"
fi
if [ "$op_data" -gt "$xram_words" ]; then
  echo "budget: the operation layer's data ($op_data words) does NOT fit its section's block XRAM ($xram_words words)" >&2
  status=1
fi
if ! fits "$state" "$EBSS_WORDS"; then
  echo "budget: controller state ($state words) exceeds ${MARGIN_PCT} % of the $EBSS_WORDS words of .ebss" >&2
  status=1
fi
if [ "$image" = im ]; then law_members IM "$cm0" "$app" "$main_dir" >/dev/null || status=1
else law_members PM "$cm0" "$app" "$main_dir" >/dev/null || status=1; fi
[ $status -eq 0 ] && echo "budget: the flash build of the $image image fits with a $((100 - MARGIN_PCT)) % margin (estimate; confirm with the cl2000 map file, docs/f2812.md)"
exit $status
