/* vergence — preloaded into the leak checks: keeps the libraries named in
 * VG_KEEP_LOADED (colon-separated paths) mapped until the process exits.
 * The Vulkan loader unloads driver and layers before LeakSanitizer reports;
 * their allocations then show as "<unknown module>" and no suppression in
 * lsan.supp can match them. Preloading the validation layer itself does not
 * work: its vk* symbols would shadow the loader's. RTLD_LOCAL keeps them out
 * of the global scope, RTLD_NODELETE keeps them mapped. */
#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

__attribute__((constructor)) static void keep_loaded(void)
{
    const char *list = getenv("VG_KEEP_LOADED");
    char path[4096];
    while (list && *list) {
        const char *end = strchr(list, ':');
        size_t n = end ? (size_t)(end - list) : strlen(list);
        if (n > 0 && n < sizeof path) {
            memcpy(path, list, n);
            path[n] = '\0';
            dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
        }
        list = end ? end + 1 : NULL;
    }
}
