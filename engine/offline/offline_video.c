/* vergence — `optimize --video` and `--depth-video`: a colour video and a
 * grey depth video decoded by Debian's ffmpeg (any container and codec it
 * reads) into PNG frames in a temporary folder, which the pipeline then
 * reads as --image and as a 16-bit depth PNG sequence. ffmpeg runs without a shell
 * (posix_spawn, the file name as one argument); its own error message is
 * quoted in ours. */
#include "offline_internal.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/log.h"
#include "figure/figure.h"

extern char **environ;

/* The last non-empty line of a small text file (ffmpeg's stderr), or "". */
static void last_line(const char *path, char *out, size_t cap)
{
    out[0] = 0;
    FILE *f = fopen(path, "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = 0;
        if (line[0])
            snprintf(out, cap, "%s", line);
    }
    if (f)
        fclose(f);
}

/* The temporary folder the frames go to, before the run names its inputs. */
vg_status offline_video_prepare(offline_seq *s)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(s->video_dir, sizeof s->video_dir, "%s/vergence-video-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (strlen(s->video_dir) > OFFLINE_PATH_CAP - 64 || !mkdtemp(s->video_dir)) {
        vg_error("%s: cannot make a folder for --video's frames: %s", s->video_dir, strerror(errno));
        s->video_dir[0] = 0;
        return VG_ERR_IO;
    }
    return VG_OK;
}

/* One video's frames first..last into s->video_dir as PREFIX_%d.png of
 * pixel format fmt (rgb24 for colour, gray16be for depth: 8-bit grey comes
 * out as v * 257). */
static vg_status decode(offline_seq *s, const char *file, const char *flag, const char *prefix, const char *fmt)
{
    const offline_desc *d = s->desc;
    char ffmpeg[4096];
    struct stat sb;
    if (stat(file, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        vg_error("%s: %s: %s", file, flag, stat(file, &sb) != 0 ? strerror(errno) : "not a file");
        return VG_ERR_IO;
    }
    if (!figure_find_ffmpeg(ffmpeg, sizeof ffmpeg)) {
        vg_error("%s: %s needs ffmpeg on PATH to decode it (Debian: apt-get install ffmpeg)", file, flag);
        return VG_ERR_ARG;
    }
    char select[96], start[16], count[16], frames[OFFLINE_PATH_CAP + 32], log[OFFLINE_PATH_CAP + 32];
    snprintf(select, sizeof select, "select=between(n\\,%d\\,%d)", d->first, d->last);
    snprintf(start, sizeof start, "%d", d->first);
    snprintf(count, sizeof count, "%d", d->last - d->first + 1);
    snprintf(frames, sizeof frames, "%s/%s_%%d.png", s->video_dir, prefix);
    snprintf(log, sizeof log, "%s/ffmpeg.txt", s->video_dir);
    char *argv[] = {ffmpeg, "-nostdin", "-v", "error", "-i", (char *)file, "-vf", select, "-fps_mode", "passthrough",
                    "-frames:v", count, "-start_number", start, "-pix_fmt", (char *)fmt, frames, NULL};
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, log, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    vg_info("optimize: decoding frames %d:%d of %s with ffmpeg", d->first, d->last, file);
    pid_t pid;
    int rc = posix_spawn(&pid, ffmpeg, &fa, NULL, argv, environ), status = 0;
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
        vg_error("%s: could not start %s: %s", file, ffmpeg, strerror(rc));
        return VG_ERR_IO;
    }
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    char why[512];
    last_line(log, why, sizeof why);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        vg_error("%s: ffmpeg cannot decode it: %s", file, why[0] ? why : "(no message)");
        return VG_ERR_FORMAT;
    }
    /* Frames past the video's end are simply not written. */
    int have = 0;
    char path[OFFLINE_PATH_CAP + 32];
    for (int t = d->first; t <= d->last; t++, have++) {
        snprintf(path, sizeof path, "%s/%s_%d.png", s->video_dir, prefix, t);
        if (access(path, F_OK) != 0)
            break;
    }
    if (have < d->last - d->first + 1) {
        vg_error("%s: --frames %d:%d: the video ends before frame %d (frames count from 0)", file, d->first, d->last,
                 d->first + have);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

vg_status offline_video_decode(offline_seq *s)
{
    const offline_desc *d = s->desc;
    vg_status st = VG_OK;
    if (d->video_in)
        st = decode(s, d->video_in, "--video", "frame", "rgb24");
    if (st == VG_OK && d->depth_video)
        st = decode(s, d->depth_video, "--depth-video", "depth", "gray16be");
    return st;
}

void offline_video_remove(offline_seq *s)
{
    if (!s->video_dir[0])
        return;
    DIR *dir = opendir(s->video_dir);
    struct dirent *e;
    char path[OFFLINE_PATH_CAP + 300];
    while (dir && (e = readdir(dir)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(path, sizeof path, "%s/%s", s->video_dir, e->d_name);
            unlink(path);
        }
    if (dir)
        closedir(dir);
    rmdir(s->video_dir);
    s->video_dir[0] = 0;
}
