/* Standalone reproduction of a GCC 12.2 wrong-code bug (x86-64, -O3) that
 * aid_mmukf.h guards against; not part of the build.
 *
 *   gcc -O3 -std=c11 tests/unit/gcc12_outer_vect_align.c && ./a.out   -> SIGSEGV (GCC 12.2.0)
 *   clang -O3, gcc -O2, gcc -O3 -fno-tree-loop-vectorize              -> runs
 *
 * S is 16-byte aligned (long double member) and its array phi sits at 8 mod
 * 16. Outer-loop vectorization of the matrix product (variable n) computes
 * phi's misalignment as 0 (its vectorizer dump: base misalignment 8 recorded
 * for the struct pointer from the MEM_REF offset, and the same offset added
 * again as the constant offset) and loads phi[l][0..1] with an aligned mulpd.
 * With phi at 0 mod 16, or a struct of 8-byte alignment, the code is correct. */
#include <stdio.h>
#include <string.h>
#define N 16
typedef struct {
    long double ld;
    double pad;
    double phi[N][N];
    int n;
} S;
static void mat_mul(int n, double a[N][N], double b[N][N], double o[N][N])
{
    for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
            double s = 0;
            for (int l = 0; l < n; ++l) s += a[j][l] * b[l][k];
            o[j][k] = s;
        }
}
__attribute__((noinline)) void prop(S *s);
__attribute__((noinline)) void prop(S *s)
{
    double F[N][N], T[N][N];
    memset(F, 0, sizeof F);
    for (int j = 0; j < s->n; ++j) F[j][j] = 2;
    mat_mul(s->n, F, s->phi, T);
    for (int j = 0; j < s->n; ++j)
        for (int k = 0; k < s->n; ++k) s->phi[j][k] = T[j][k];
}
static S g;
int main(void)
{
    g.n = 12;
    for (int j = 0; j < N; ++j) g.phi[j][j] = 1;
    prop(&g);
    printf("phi at %zu mod 16: phi[0][0] = %g (expected 2)\n", (size_t)((unsigned long)&g.phi % 16), g.phi[0][0]);
    return 0;
}
