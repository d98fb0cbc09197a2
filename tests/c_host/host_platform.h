/* What host.c needs of its platform: loading a library and finding its functions, an
 * absolute path, a monotonic clock, and the FMU's names for this platform (its binaries
 * folder in FMI 2.0 and 3.0, and the library's suffix).
 *
 * POSIX (Linux, macOS): dlopen and dlsym, realpath, clock_gettime.
 * Windows (MinGW, UCRT; also under wine): LoadLibraryA and GetProcAddress, _fullpath,
 * QueryPerformanceCounter.
 */
#ifndef HOST_PLATFORM_H
#define HOST_PLATFORM_H

#include <stdio.h>
#include <stdlib.h>

#ifdef _WIN32
#include <windows.h>

typedef HMODULE Library;
#define LIBRARY_SUFFIX ".dll"
#define FMI2_PLATFORM "win64"
#define FMI3_PLATFORM "x86_64-windows"
#define PATH_SIZE 4096

/* LoadLibrary wants backslashes */
static Library library_open(const char *path) {
    char native[PATH_SIZE + 256];
    snprintf(native, sizeof native, "%s", path);
    for (char *p = native; *p; p++)
        if (*p == '/') *p = '\\';
    return LoadLibraryA(native);
}
static void *library_symbol(Library lib, const char *name) {
    return (void *)(size_t)GetProcAddress(lib, name); /* a function pointer, as dlsym's */
}
static void library_close(Library lib) { FreeLibrary(lib); }
static const char *library_error(void) {
    static char text[64];
    snprintf(text, sizeof text, "Windows error %lu", (unsigned long)GetLastError());
    return text;
}
/* The absolute path of `path` in `out` (PATH_SIZE bytes); 0 if there is none. */
static int absolute_path(const char *path, char *out) {
    return _fullpath(out, path, PATH_SIZE) != NULL && GetFileAttributesA(out) != INVALID_FILE_ATTRIBUTES;
}
static double seconds(void) {
    LARGE_INTEGER now, frequency;
    QueryPerformanceCounter(&now);
    QueryPerformanceFrequency(&frequency);
    return (double)now.QuadPart / (double)frequency.QuadPart;
}

#else
#include <dlfcn.h>
#include <limits.h>
#include <time.h>

typedef void *Library;
#define PATH_SIZE (PATH_MAX + 1)
#ifdef __APPLE__
#define LIBRARY_SUFFIX ".dylib"
#define FMI2_PLATFORM "darwin64"
#ifdef __aarch64__
#define FMI3_PLATFORM "aarch64-darwin"
#else
#define FMI3_PLATFORM "x86_64-darwin"
#endif
#else
#define LIBRARY_SUFFIX ".so"
#ifdef __aarch64__
#define FMI2_PLATFORM NULL /* FMI 2.0 names no aarch64 Linux platform */
#define FMI3_PLATFORM "aarch64-linux"
#else
#define FMI2_PLATFORM "linux64"
#define FMI3_PLATFORM "x86_64-linux"
#endif
#endif

static Library library_open(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *library_symbol(Library lib, const char *name) { return dlsym(lib, name); }
static void library_close(Library lib) { dlclose(lib); }
static const char *library_error(void) { return dlerror(); }
static int absolute_path(const char *path, char *out) { return realpath(path, out) != NULL; }
static double seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
#endif

#endif
