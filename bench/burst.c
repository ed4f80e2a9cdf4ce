/*
 * A known disturbance for checking the side-by-side benchmark's units:
 * runs at SCHED_FIFO 99 on one CPU and, COUNT times, busy-waits BURST_US
 * microseconds every EVERY_US microseconds (bench/side-by-side.sh builds
 * it with cc). A burst that lands inside a HAL thread's function list
 * (the thread runs at a lower priority on the same CPU) lengthens that
 * cycle's thread time by the burst, in whatever unit the HAL reports.
 *
 *   burst CPU BURST_US EVERY_US COUNT
 */
#define _GNU_SOURCE
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static uint64_t now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: burst CPU BURST_US EVERY_US COUNT\n");
        return 2;
    }
    int cpu = atoi(argv[1]);
    uint64_t burst = strtoull(argv[2], NULL, 10) * 1000u;
    uint64_t every = strtoull(argv[3], NULL, 10) * 1000u;
    long count = atol(argv[4]);
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (sched_setaffinity(0, sizeof set, &set) != 0) {
        perror("burst: sched_setaffinity");
        return 1;
    }
    struct sched_param sp = {.sched_priority = 99};
    if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0) {
        perror("burst: sched_setscheduler");
        return 1;
    }
    uint64_t next = now_ns() + every;
    for (long i = 0; i < count; i++) {
        struct timespec ts = {(time_t)(next / 1000000000u), (long)(next % 1000000000u)};
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
        uint64_t end = now_ns() + burst;
        while (now_ns() < end) {
        }
        next += every;
    }
    return 0;
}
