#!/usr/bin/env bash
# Firmware CI: cross-compile for the STM32F302R8 (Cortex-M4F, hard float, -Os), print the
# size, fail over budget (flash 32 KB, static RAM 16 KB), then fuzz the decoder briefly
# with a fixed seed when clang is available. Run from anywhere; output in build-fw-arm/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
out="${MARVIN_FW_BUILD:-$root/build-fw-arm}"
mkdir -p "$out"

FLASH_BUDGET=$((32 * 1024))
RAM_BUDGET=$((16 * 1024))

echo "-- cross-compiling the firmware (arm-none-eabi-gcc -mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard -Os)"
make -s -C "$here/target/stm32f302" BUILD="$out/stm32f302" all
elf="$out/stm32f302/marvin-fw.elf"
arm-none-eabi-size "$elf"
read -r text data bss _ < <(arm-none-eabi-size "$elf" | awk 'NR == 2 {print $1, $2, $3}')
flash=$((text + data))
ram=$((data + bss))
echo "firmware flash: $flash bytes of $FLASH_BUDGET ($(ls -l "$out/stm32f302/marvin-fw.bin" | awk '{print $5}') bytes .bin)"
echo "firmware static RAM: $ram bytes of $RAM_BUDGET"
status=0
if [ "$flash" -gt "$FLASH_BUDGET" ]; then echo "FAIL: flash use over budget" >&2; status=1; fi
if [ "$ram" -gt "$RAM_BUDGET" ]; then echo "FAIL: static RAM use over budget" >&2; status=1; fi
[ "$status" -eq 0 ] || exit "$status"

if command -v clang >/dev/null 2>&1; then
  echo "-- libFuzzer: decoder and core, fixed seed, short run"
  fuzz="$out/decoder_fuzz"
  clang -std=c11 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
    -I"$here" "$here/fuzz/decoder_fuzz.c" "$here/protocol/marvin_protocol.c" \
    "$here/core/marvin_core.c" "$here/core/sonar.c" "$here/fake/fake_body.c" -o "$fuzz"
  rm -rf "$out/fuzz-corpus" && mkdir -p "$out/fuzz-corpus"  # fresh: the fixed seed reproduces the run
  "$fuzz" -seed=1 -runs=50000 -max_total_time=60 -max_len=512 "$out/fuzz-corpus" 2>&1 | tail -n 3
else
  echo "-- clang not found: skipping the decoder fuzzer"
fi
echo "firmware CI passed"
