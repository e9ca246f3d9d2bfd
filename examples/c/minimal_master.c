/* A minimal FMI 2.0 co-simulation master for GearedRotor.fmu in plain C.
 *
 * It loads binaries/linux64/GearedRotor.so of an extracted .fmu, sets one parameter,
 * steps 10 ms with a communication step of 0.1 ms and prints time, T1 and Fn.
 * The few FMI 2.0 types it needs are declared here, so no header is required.
 *
 *   unzip GearedRotor.fmu -d GearedRotor
 *   cc examples/c/minimal_master.c -o minimal_master -ldl
 *   ./minimal_master GearedRotor
 *
 * Value references and the GUID come from GearedRotor/modelDescription.xml (the GUID is
 * passed on the command line by tests/test_c_master.py; a real master reads it from
 * the XML).
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

#define LOAD(name) \
    if (!(name = dlsym(lib, #name))) { fprintf(stderr, "missing %s\n", #name); return 1; }

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: %s EXTRACTED_FMU_DIR GUID [mu]\n", argv[0]);
        return 2;
    }
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
    fmi2Component c = fmi2Instantiate("gears", 1 /* fmi2CoSimulation */, argv[2], NULL, &cb, 0, 0);
    if (!c) { fprintf(stderr, "fmi2Instantiate failed\n"); return 1; }

    const fmi2ValueReference vr_mu = 29 /* mu */, vr_out[2] = {42 /* T1 */, 47 /* Fn */};
    fmi2Real mu = argc > 3 ? atof(argv[3]) : 0.05, out[2];
    const fmi2Real h = 1e-4, stop = 0.01;
    if (fmi2SetReal(c, &vr_mu, 1, &mu) > 1 || fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, stop) > 1 ||
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
