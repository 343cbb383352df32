/* core/ on its own: the progress line. Run: test_core NAME. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../test.h"
#include "core/log.h"

/* A job's progress says the time left once a second has passed, from its
 * pace so far: a quarter done after 1.2 s leaves about 3.6 s. */
static int progress_time_left(void)
{
    char path[] = "/tmp/vergence-progress-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0, "temporary file");
    fflush(stderr);
    int saved = dup(STDERR_FILENO);
    CHECK(saved >= 0 && dup2(fd, STDERR_FILENO) >= 0, "stderr to a file");
    vg_progress("job", 0, 4);
    nanosleep(&(struct timespec){1, 200000000}, NULL);
    vg_progress("job", 1, 4);
    vg_progress("job", 4, 4);
    fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    char text[512] = {0};
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
    text[n] = 0;
    if (f)
        fclose(f);
    close(fd);
    unlink(path);
    printf("stderr (not a terminal):\n%s", text);
    int left = -1;
    const char *line = strstr(text, "job 1/4, ");
    CHECK(line && sscanf(line, "job 1/4, %d s left", &left) == 1, "no time left on the line of 1/4");
    CHECK(left >= 3 && left <= 6, "%d s left after a quarter in 1.2 s", left);
    CHECK(strstr(text, "job 0/4\n") && strstr(text, "job 4/4\n"), "the first and last lines say no time left");
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"progress_time_left", progress_time_left},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
