/* The loop of `windrive bench torsional` through the FMI boundary (three inputs set, fmi2DoStep, the
 * HSS torque read), on a torsional binary's C symbols and nothing else, for callgrind: the
 * instructions of each entry point per communication step, without the host's own code.
 *
 *   cc -O2 -o target/torsional_loop benches/torsional_loop.c -ldl
 *   valgrind --tool=callgrind --callgrind-out-file=target/loop.cg \
 *     target/torsional_loop target/release/libtorsional.so 10000
 *   callgrind_annotate --inclusive=yes target/loop.cg | grep -E '\?\?\?:fmi2(SetReal|DoStep|GetReal) '
 *
 * and divide by the steps (10 000). Drivetrain D at full fidelity with the default implicit
 * integrator at 1 ms, rated rotor and generator torque from the start (the bench's step at t = 0).
 * Prints the last HSS torque and the sum over the run in hexadecimal (equal lines, equal bits), then
 * the loop's wall time per step, which `benches/torsional_ab.py --loop` compares between two builds. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef void *Component;
typedef Component (*Instantiate)(const char *, int, const char *, const char *, const void *, int, int);
typedef int (*Setup)(Component, int, double, double, int, double);
typedef int (*Call)(Component);
typedef int (*Reals)(Component, const unsigned *, size_t, const double *);
typedef int (*GetReals)(Component, const unsigned *, size_t, double *);
typedef int (*Strings)(Component, const unsigned *, size_t, const char **);
typedef int (*DoStep)(Component, double, double, int);

/* value references of modelDescription/torsional.xml */
enum { PRESET = 0, FIDELITY = 1, INTEGRATOR = 2, MAX_INTERNAL_STEP = 3, ROTOR_TORQUE = 20,
       GENERATOR_TORQUE = 21, BRAKE_COMMAND = 22, RATED_ROTOR_TORQUE = 32,
       RATED_GENERATOR_TORQUE = 33, HSS_TORQUE = 45 };

static void *symbol(void *lib, const char *name) {
    void *s = dlsym(lib, name);
    if (!s) {
        fprintf(stderr, "%s missing\n", name);
        exit(1);
    }
    return s;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s path/to/libtorsional.so [steps]\n", argv[0]);
        return 1;
    }
    void *lib = dlopen(argv[1], RTLD_NOW);
    if (!lib) {
        fprintf(stderr, "%s\n", dlerror());
        return 1;
    }
    int steps = argc > 2 ? atoi(argv[2]) : 10000;
    /* the GUID changes with every build: read it from the binary's own model description */
    const char *xml = ((const char *(*)(void))symbol(lib, "windrive_model_description"))();
    const char *g = strstr(xml, "guid=\"") + 6;
    char guid[64];
    size_t n = (size_t)(strchr(g, '"') - g);
    memcpy(guid, g, n);
    guid[n] = 0;

    Component c = ((Instantiate)symbol(lib, "fmi2Instantiate"))("bench", 1, guid, NULL, NULL, 0, 0);
    Reals set_real = (Reals)symbol(lib, "fmi2SetReal");
    GetReals get_real = (GetReals)symbol(lib, "fmi2GetReal");
    DoStep do_step = (DoStep)symbol(lib, "fmi2DoStep");
    ((Setup)symbol(lib, "fmi2SetupExperiment"))(c, 0, 0.0, 0.0, 0, 0.0);
    const unsigned strings_vr[3] = {PRESET, FIDELITY, INTEGRATOR};
    const char *strings[3] = {"D", "full", "implicit"};
    ((Strings)symbol(lib, "fmi2SetString"))(c, strings_vr, 3, strings);
    const unsigned step_vr = MAX_INTERNAL_STEP;
    const double step = 1e-3;
    set_real(c, &step_vr, 1, &step);
    ((Call)symbol(lib, "fmi2EnterInitializationMode"))(c);
    ((Call)symbol(lib, "fmi2ExitInitializationMode"))(c);
    const unsigned rated_vr[2] = {RATED_ROTOR_TORQUE, RATED_GENERATOR_TORQUE};
    double rated[2];
    get_real(c, rated_vr, 2, rated);

    const unsigned inputs_vr[3] = {ROTOR_TORQUE, GENERATOR_TORQUE, BRAKE_COMMAND};
    const unsigned hss_vr = HSS_TORQUE;
    double hss = 0.0, sum = 0.0;
    struct timespec start, end;
    clock_gettime(CLOCK_MONOTONIC, &start);
    for (int i = 0; i < steps; i++) {
        const double inputs[3] = {rated[0], rated[1], 0.0};
        if (set_real(c, inputs_vr, 3, inputs) || do_step(c, i * step, step, 1) ||
            get_real(c, &hss_vr, 1, &hss)) {
            fprintf(stderr, "step %d failed\n", i);
            return 1;
        }
        sum += hss;
    }
    clock_gettime(CLOCK_MONOTONIC, &end);
    printf("hss %a sum %a\n", hss, sum);
    printf("ns per step %.2f\n", ((end.tv_sec - start.tv_sec) * 1e9 + (end.tv_nsec - start.tv_nsec)) / steps);
    return 0;
}
