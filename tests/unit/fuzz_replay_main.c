/* Replays libFuzzer inputs through a harness's LLVMFuzzerTestOneInput without
 * libFuzzer: each file named on the command line is run once; a broken
 * invariant aborts (the harness's FAIL), so the exit status says whether the
 * findings kept in tests/fuzz_findings/ stay mended. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv)
{
    static uint8_t buf[1 << 16];
    if (argc < 2) {
        fprintf(stderr, "usage: %s INPUT...\n", argv[0]);
        return 2;
    }
    for (int i = 1; i < argc; ++i) {
        FILE *f = fopen(argv[i], "rb");
        if (f == NULL) {
            fprintf(stderr, "%s: cannot open\n", argv[i]);
            return 2;
        }
        const size_t n = fread(buf, 1, sizeof buf, f);
        fclose(f);
        (void)LLVMFuzzerTestOneInput(buf, n);
        printf("ok   %s (%zu bytes)\n", argv[i], n);
    }
    return 0;
}
