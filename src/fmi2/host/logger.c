/* The FMI 2.0 logger is a C variadic function, which stable Rust cannot define. This shim formats
 * the message with vsnprintf and hands the finished string to Rust: to the sink Rust registers once
 * with windrive_set_log_sink before any instance can log. A registered pointer, not a named Rust
 * symbol: a named one would be exported by every FMU library built with the master's code linked. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

typedef void (*windrive_sink)(void *env, const char *instance, int status, const char *category,
                              const char *message);

static windrive_sink windrive_log_sink = NULL;

void windrive_set_log_sink(windrive_sink sink) { windrive_log_sink = sink; }

void windrive_fmi2_logger(void *env, const char *instance, int status, const char *category,
                          const char *format, ...) {
    char small[1024];
    va_list args, again;
    if (windrive_log_sink == NULL) {
        return;
    }
    if (format == NULL) {
        windrive_log_sink(env, instance, status, category, "(null message)");
        return;
    }
    va_start(args, format);
    va_copy(again, args);
    int n = vsnprintf(small, sizeof small, format, args);
    va_end(args);
    if (n < 0) {
        windrive_log_sink(env, instance, status, category, format);
    } else if ((size_t)n < sizeof small) {
        windrive_log_sink(env, instance, status, category, small);
    } else {
        char *big = malloc((size_t)n + 1);
        if (big != NULL) {
            vsnprintf(big, (size_t)n + 1, format, again);
            windrive_log_sink(env, instance, status, category, big);
            free(big);
        } else {
            windrive_log_sink(env, instance, status, category, small);
        }
    }
    va_end(again);
}
