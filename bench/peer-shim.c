/*
 * LD_PRELOAD library for running LinuxCNC 2.9's rtapi_app in the
 * side-by-side benchmark (bench/side-by-side.sh builds it with cc).
 *
 * What it changes, and only that:
 *  - iopl() reports success without doing anything: rtapi_app asks for
 *    port I/O before it uses SCHED_FIFO, which a VM's kernel or a sandbox
 *    refuses, and the benchmark's components touch no ports.
 *  - setrlimit(RLIMIT_RTPRIO, ...) reports success when the call is
 *    refused: rtapi_app raises that limit before SCHED_FIFO, which needs
 *    CAP_SYS_RESOURCE even for root; as root, SCHED_FIFO works without it.
 *  - In rtapi_app only (the process that runs LinuxCNC's threads):
 *    with SBS_TIMER_SLACK_NS set, the process's first thread takes that
 *    timer slack before main(), so every thread it creates inherits it
 *    (this project's executor sets 1 ns on its threads).
 *    With SBS_CPU_LATENCY=1, it holds a zero CPU wake-up latency request
 *    (/dev/cpu_dma_latency) for the process's life, as this project's
 *    host does where it may.
 * The last two make the matched series: both sides run with the same
 * settings, so a difference in the table comes from the executors.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

int iopl(int level)
{
    (void)level;
    return 0;
}

typedef int (*setrlimit_fn)(__rlimit_resource_t, const struct rlimit *);

int setrlimit(__rlimit_resource_t resource, const struct rlimit *rlim)
{
    setrlimit_fn real = (setrlimit_fn)dlsym(RTLD_NEXT, "setrlimit");
    int rc = real ? real(resource, rlim) : -1;
    if (rc != 0 && resource == RLIMIT_RTPRIO) {
        errno = 0;
        return 0;
    }
    return rc;
}

__attribute__((constructor)) static void sbs_matched_settings(void)
{
    if (strcmp(program_invocation_short_name, "rtapi_app") != 0)
        return;
    const char *slack = getenv("SBS_TIMER_SLACK_NS");
    const char *latency = getenv("SBS_CPU_LATENCY");
    if (slack && *slack) {
        unsigned long ns = strtoul(slack, NULL, 10);
        if (ns > 0)
            prctl(PR_SET_TIMERSLACK, ns, 0, 0, 0);
    }
    if (latency && strcmp(latency, "1") == 0) {
        /* Kept open on purpose: the request lasts as long as the fd. */
        int fd = open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
        if (fd >= 0) {
            int32_t zero = 0;
            if (write(fd, &zero, sizeof zero) != (ssize_t)sizeof zero)
                close(fd);
        }
    }
}
