/* A minimal FMI 2.0 co-simulation master for GearedRotor.fmu in plain C.
 *
 * It loads binaries/linux64/GearedRotor.so of an extracted .fmu, sets one parameter,
 * steps 10 ms with a communication step of 0.1 ms and prints time, T1 and Fn.
 * The few FMI 2.0 types it needs are declared here, so no header is required.
 *
 *   unzip GearedRotor.fmu -d GearedRotor
 *   cc examples/c/minimal_master.c -o minimal_master -ldl
 *   ./minimal_master GearedRotor [mu]
 *
 * The GUID and the value references are read from GearedRotor/modelDescription.xml by
 * name (a small attribute scanner, enough for this file; a larger master would use an XML
 * library), so a rebuilt .fmu with renumbered variables needs no change here.
 */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Boolean;
typedef int fmi2Status; /* 0 OK, 1 Warning, 2 Discard, 3 Error, 4 Fatal */

typedef struct {
    void (*logger)(void *, const char *, fmi2Status, const char *, const char *, ...);
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} fmi2CallbackFunctions;

static void logger(void *env, const char *instance, fmi2Status status, const char *category,
                   const char *message, ...) {
    va_list args;
    (void)env;
    fprintf(stderr, "[%s %s %d] ", instance, category, status);
    va_start(args, message);
    vfprintf(stderr, message, args);
    va_end(args);
    fputc('\n', stderr);
}

/* The whole file as a NUL-terminated string (NULL on failure). */
static char *read_file(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) { free(s); s = NULL; }
    if (s) s[n] = '\0';
    fclose(f);
    return s;
}

/* The value of attribute `attr` in the XML start tag at `tag` (up to its '>') into out. */
static int attribute(const char *tag, const char *attr, char *out, size_t size) {
    const char *end = strchr(tag, '>');
    char key[64];
    snprintf(key, sizeof key, " %s=\"", attr);
    const char *p = strstr(tag, key);
    if (!p || !end || p > end) return 0;
    p += strlen(key);
    const char *q = strchr(p, '"');
    if (!q || q > end || (size_t)(q - p) >= size) return 0;
    memcpy(out, p, (size_t)(q - p));
    out[q - p] = '\0';
    return 1;
}

/* The valueReference of the ScalarVariable called `name`, or -1. */
static long value_reference(const char *xml, const char *name) {
    char buf[256];
    for (const char *tag = strstr(xml, "<ScalarVariable "); tag;
         tag = strstr(tag + 1, "<ScalarVariable ")) {
        if (attribute(tag, "name", buf, sizeof buf) && strcmp(buf, name) == 0)
            return attribute(tag, "valueReference", buf, sizeof buf) ? strtol(buf, NULL, 10) : -1;
    }
    return -1;
}

#define LOAD(name) \
    if (!(name = dlsym(lib, #name))) { fprintf(stderr, "missing %s\n", #name); return 1; }

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s EXTRACTED_FMU_DIR [mu]\n", argv[0]);
        return 2;
    }
    char path[4096], guid[128];
    snprintf(path, sizeof path, "%s/modelDescription.xml", argv[1]);
    char *xml = read_file(path);
    if (!xml) { fprintf(stderr, "cannot read %s\n", path); return 1; }
    const char *root = strstr(xml, "<fmiModelDescription");
    long vr_mu = value_reference(xml, "mu"), vr_t1 = value_reference(xml, "T1"),
         vr_fn = value_reference(xml, "Fn");
    if (!root || !attribute(root, "guid", guid, sizeof guid) || vr_mu < 0 || vr_t1 < 0 || vr_fn < 0) {
        fprintf(stderr, "%s: no guid, or no variable mu, T1 or Fn\n", path);
        return 1;
    }
    free(xml);
    char so[4096];
    snprintf(so, sizeof so, "%s/binaries/linux64/GearedRotor.so", argv[1]);
    void *lib = dlopen(so, RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 1; }

    fmi2Component (*fmi2Instantiate)(const char *, int, const char *, const char *,
                                     const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
    fmi2Status (*fmi2SetupExperiment)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real,
                                      fmi2Boolean, fmi2Real);
    fmi2Status (*fmi2EnterInitializationMode)(fmi2Component);
    fmi2Status (*fmi2ExitInitializationMode)(fmi2Component);
    fmi2Status (*fmi2SetReal)(fmi2Component, const fmi2ValueReference *, size_t, const fmi2Real *);
    fmi2Status (*fmi2GetReal)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Real *);
    fmi2Status (*fmi2DoStep)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);
    fmi2Status (*fmi2Terminate)(fmi2Component);
    void (*fmi2FreeInstance)(fmi2Component);
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2DoStep)
    LOAD(fmi2Terminate) LOAD(fmi2FreeInstance)

    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2Component c = fmi2Instantiate("gears", 1 /* fmi2CoSimulation */, guid, NULL, &cb, 0, 0);
    if (!c) { fprintf(stderr, "fmi2Instantiate failed\n"); return 1; }

    const fmi2ValueReference vr_set = (fmi2ValueReference)vr_mu,
                             vr_out[2] = {(fmi2ValueReference)vr_t1, (fmi2ValueReference)vr_fn};
    fmi2Real mu = argc > 2 ? atof(argv[2]) : 0.05, out[2];
    const fmi2Real h = 1e-4, stop = 0.01;
    if (fmi2SetReal(c, &vr_set, 1, &mu) > 1 || fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, stop) > 1 ||
        fmi2EnterInitializationMode(c) > 1 || fmi2ExitInitializationMode(c) > 1) {
        fprintf(stderr, "initialisation failed\n");
        return 1;
    }
    printf("time,T1,Fn\n");
    for (int n = 0; n < 100; n++) {
        fmi2Real t = n * h;
        if (fmi2DoStep(c, t, h, 1) > 1) { fprintf(stderr, "fmi2DoStep failed at %g\n", t); return 1; }
        fmi2GetReal(c, vr_out, 2, out);
        printf("%.6g,%.10g,%.10g\n", t + h, out[0], out[1]);
    }
    fmi2Terminate(c);
    fmi2FreeInstance(c);
    dlclose(lib);
    return 0;
}
