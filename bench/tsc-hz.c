/*
 * Prints the TSC's rate in ticks per second, measured against
 * CLOCK_MONOTONIC_RAW over about a quarter of a second (the median of five
 * measurements), for converting LinuxCNC 2.9's thread and function times,
 * which are TSC ticks, to ns (bench/side-by-side.sh builds it with cc).
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <x86intrin.h>

static uint64_t raw_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC_RAW, &t);
    return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(void)
{
    double hz[5];
    for (int i = 0; i < 5; i++) {
        uint64_t t0 = raw_ns(), c0 = __rdtsc();
        struct timespec pause = {0, 50000000};
        nanosleep(&pause, NULL);
        uint64_t t1 = raw_ns(), c1 = __rdtsc();
        hz[i] = (double)(c1 - c0) * 1e9 / (double)(t1 - t0);
    }
    qsort(hz, 5, sizeof hz[0], by_value);
    printf("%.0f\n", hz[2]);
    return 0;
}
