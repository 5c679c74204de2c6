/* bench.h — `firmness_model bench`: full evaluations per second. */
#ifndef AF_BENCH_H
#define AF_BENCH_H

/* argv[first..argc): [--seconds S] and model flags. Returns the exit code. */
int af_bench_main(int argc, char **argv, int first);

#endif
