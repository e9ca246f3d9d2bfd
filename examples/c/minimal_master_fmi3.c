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
 *   ./minimal_master_fmi3 GearedRotor-fmi3 TOKEN
 *
 * Value references and the instantiation token come from modelDescription.xml (the token
 * is passed on the command line by tests/test_c_master_fmi3.py; a real master reads it
 * from the XML).
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

#define LOAD(name) \
    if (!(name = dlsym(lib, #name))) { fprintf(stderr, "missing %s\n", #name); return 1; }

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: %s EXTRACTED_FMU_DIR TOKEN [mu [early]]\n", argv[0]);
        return 2;
    }
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

    bool early_allowed = argc > 4 && strcmp(argv[4], "early") == 0;
    fmi3Instance c = fmi3InstantiateCoSimulation("gears", argv[2], NULL, false, false, false,
                                                 early_allowed, NULL, 0, NULL, logger, NULL);
    if (!c) { fprintf(stderr, "fmi3InstantiateCoSimulation failed\n"); return 1; }

    const fmi3ValueReference vr_mu = 29 /* mu */, vr_out[2] = {42 /* T1 */, 47 /* Fn */};
    fmi3Float64 mu = argc > 3 ? atof(argv[3]) : 0.05, out[2];
    const fmi3Float64 h = 1e-4, stop = 0.01;
    if (fmi3SetFloat64(c, &vr_mu, 1, &mu, 1) > 1 ||
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
