#!/usr/bin/env bash
# The firmware library must not call the heap, stdio or process exit.
# Lists every undefined symbol of the archive that is not the firmware's own
# (gg_*) and fails on the forbidden ones. Usage: check_fw_symbols.sh <nm> <lib.a>
set -euo pipefail
nm_tool=$1
lib=$2
undef=$("$nm_tool" -u "$lib" | awk 'NF==2 && $1=="U" {print $2}' | grep -v '^gg_' | sort -u || true)
echo "external symbols used by $(basename "$lib"): ${undef:-none}"
bad=$(printf '%s\n' "$undef" | grep -E '^(malloc|calloc|realloc|free|aligned_alloc|posix_memalign|printf|fprintf|sprintf|snprintf|vprintf|puts|putchar|fputs|fwrite|fopen|fclose|exit|_exit|abort|atexit|__assert_fail|_sbrk|sbrk)$' || true)
if [ -n "$bad" ]; then
  echo "FORBIDDEN in firmware: $bad"
  exit 1
fi
echo "ok: no heap, stdio or exit"
