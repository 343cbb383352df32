/* Replays inputs through a fuzz target without libFuzzer: every argument is
 * a file or a folder of files. Exits 0 when every input ran (a crash or a
 * sanitizer report ends the process with a failure). */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/io.h"
#include "core/log.h"
#include "fuzz.h"

static int run_file(const char *path)
{
    uint8_t *data;
    size_t size;
    if (vg_file_read(path, &data, &size) != VG_OK)
        return 1;
    LLVMFuzzerTestOneInput(data, size);
    free(data);
    return 0;
}

int main(int argc, char **argv)
{
    int ran = 0, failed = 0;
    for (int i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "fuzz replay: %s: no such file or folder\n", argv[i]);
            return 2;
        }
        if (!S_ISDIR(st.st_mode)) {
            failed += run_file(argv[i]);
            ran++;
            continue;
        }
        DIR *d = opendir(argv[i]);
        struct dirent *e;
        while (d && (e = readdir(d))) {
            if (e->d_name[0] == '.')
                continue;
            char path[4096];
            snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
            if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
                failed += run_file(path);
                ran++;
            }
        }
        if (d)
            closedir(d);
    }
    printf("replayed %d input(s)%s\n", ran, failed ? ", some unreadable" : "");
    return ran == 0 || failed ? 1 : 0;
}
