/* A minimal FMI 3.0 co-simulation master for GearedRotor-fmi3.fmu in plain C (C99).
 *
 * It loads binaries/x86_64-linux/GearedRotor.so of an extracted .fmu, sets one parameter,
 * steps 10 ms with a communication step of 0.1 ms and prints time, T1 and Fn; with a
 * fourth argument "early" it allows early return (earlyReturnAllowed) and prints where a
 * step returned early. The few FMI 3.0 types it needs are declared here (fmi3Boolean is
 * C99 bool), so no header is required.
 *
 *   unzip GearedRotor-fmi3.fmu -d GearedRotor-fmi3
 *   cc -std=c99 examples/c/minimal_master_fmi3.c -o minimal_master_fmi3 -ldl
 *   ./minimal_master_fmi3 GearedRotor-fmi3 [mu [early]]
 *
 * The instantiation token and the value references of mu, T1 and Fn are read from the
 * extracted modelDescription.xml by name (as examples/c/minimal_master.c does for 2.0).
 */
#include <dlfcn.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *fmi3Instance;
typedef uint32_t fmi3ValueReference;
typedef double fmi3Float64;
typedef bool fmi3Boolean;
typedef int fmi3Status; /* 0 OK, 1 Warning, 2 Discard, 3 Error, 4 Fatal */
typedef void (*fmi3LogMessageCallback)(void *env, fmi3Status status, const char *category,
                                       const char *message);

static void logger(void *env, fmi3Status status, const char *category, const char *message) {
    (void)env;
    fprintf(stderr, "[%s %d] %s\n", category, status, message); /* not a format string */
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

/* The valueReference of the Float64 variable called `name`, or -1 (FMI 3.0: one element
 * per type, <Float64 name=... valueReference=...>). */
static long value_reference(const char *xml, const char *name) {
    char buf[256];
    for (const char *tag = strstr(xml, "<Float64 "); tag; tag = strstr(tag + 1, "<Float64 ")) {
        if (attribute(tag, "name", buf, sizeof buf) && strcmp(buf, name) == 0)
            return attribute(tag, "valueReference", buf, sizeof buf) ? strtol(buf, NULL, 10) : -1;
    }
    return -1;
}

#define LOAD(name) \
    if (!(name = dlsym(lib, #name))) { fprintf(stderr, "missing %s\n", #name); return 1; }

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s EXTRACTED_FMU_DIR [mu [early]]\n", argv[0]);
        return 2;
    }
    char path[4096], token[128];
    snprintf(path, sizeof path, "%s/modelDescription.xml", argv[1]);
    char *xml = read_file(path);
    if (!xml) { fprintf(stderr, "cannot read %s\n", path); return 1; }
    const char *root = strstr(xml, "<fmiModelDescription");
    long vr_mu = value_reference(xml, "mu"), vr_t1 = value_reference(xml, "T1"),
         vr_fn = value_reference(xml, "Fn");
    if (!root || !attribute(root, "instantiationToken", token, sizeof token) || vr_mu < 0 ||
        vr_t1 < 0 || vr_fn < 0) {
        fprintf(stderr, "%s: no instantiationToken, or no variable mu, T1 or Fn\n", path);
        return 1;
    }
    free(xml);
    char so[4096];
    snprintf(so, sizeof so, "%s/binaries/x86_64-linux/GearedRotor.so", argv[1]);
    void *lib = dlopen(so, RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 1; }

    fmi3Instance (*fmi3InstantiateCoSimulation)(
        const char *, const char *, const char *, fmi3Boolean, fmi3Boolean, fmi3Boolean,
        fmi3Boolean, const fmi3ValueReference *, size_t, void *, fmi3LogMessageCallback, void *);
    fmi3Status (*fmi3EnterInitializationMode)(fmi3Instance, fmi3Boolean, fmi3Float64, fmi3Float64,
                                              fmi3Boolean, fmi3Float64);
    fmi3Status (*fmi3ExitInitializationMode)(fmi3Instance);
    fmi3Status (*fmi3SetFloat64)(fmi3Instance, const fmi3ValueReference *, size_t,
                                 const fmi3Float64 *, size_t);
    fmi3Status (*fmi3GetFloat64)(fmi3Instance, const fmi3ValueReference *, size_t, fmi3Float64 *,
                                 size_t);
    fmi3Status (*fmi3DoStep)(fmi3Instance, fmi3Float64, fmi3Float64, fmi3Boolean, fmi3Boolean *,
                             fmi3Boolean *, fmi3Boolean *, fmi3Float64 *);
    fmi3Status (*fmi3Terminate)(fmi3Instance);
    void (*fmi3FreeInstance)(fmi3Instance);
    LOAD(fmi3InstantiateCoSimulation) LOAD(fmi3EnterInitializationMode)
    LOAD(fmi3ExitInitializationMode) LOAD(fmi3SetFloat64) LOAD(fmi3GetFloat64) LOAD(fmi3DoStep)
    LOAD(fmi3Terminate) LOAD(fmi3FreeInstance)

    bool early_allowed = argc > 3 && strcmp(argv[3], "early") == 0;
    fmi3Instance c = fmi3InstantiateCoSimulation("gears", token, NULL, false, false, false,
                                                 early_allowed, NULL, 0, NULL, logger, NULL);
    if (!c) { fprintf(stderr, "fmi3InstantiateCoSimulation failed\n"); return 1; }

    const fmi3ValueReference vr_set = (fmi3ValueReference)vr_mu,
                             vr_out[2] = {(fmi3ValueReference)vr_t1, (fmi3ValueReference)vr_fn};
    fmi3Float64 mu = argc > 2 ? atof(argv[2]) : 0.05, out[2];
    const fmi3Float64 h = 1e-4, stop = 0.01;
    if (fmi3SetFloat64(c, &vr_set, 1, &mu, 1) > 1 ||
        fmi3EnterInitializationMode(c, false, 0.0, 0.0, true, stop) > 1 ||
        fmi3ExitInitializationMode(c) > 1) {
        fprintf(stderr, "initialisation failed\n");
        return 1;
    }
    printf("time,T1,Fn\n");
    fmi3Float64 t = 0.0;
    for (int n = 0; n < 100; n++) {
        fmi3Boolean event, terminate, early;
        fmi3Float64 last;
        fmi3Float64 h_n = (n + 1) * h - t; /* to the next point of the grid */
        if (fmi3DoStep(c, t, h_n, true, &event, &terminate, &early, &last) > 1 || terminate) {
            fprintf(stderr, "fmi3DoStep failed at %g\n", t);
            return 1;
        }
        if (early) {
            fprintf(stderr, "early return at t = %.12g\n", last);
            n--; /* the same grid point again, from where the step stopped */
        }
        t = last;
        fmi3GetFloat64(c, vr_out, 2, out, 2);
        printf("%.6g,%.10g,%.10g\n", t, out[0], out[1]);
    }
    fmi3Terminate(c);
    fmi3FreeInstance(c);
    dlclose(lib);
    return 0;
}
