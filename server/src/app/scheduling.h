// Where the kernel runs hadald and how eagerly: hadald --cpus LIST and --sched batch|other.
//
// A lockstep server and the client that steps it take turns on the same cores. On a small machine with
// several servers (hadal.env.VectorEnv) two things cost throughput (docs/benchmarks.md, "Lockstep round
// trip and the Python client"): the kernel migrating a server's threads between cores (cold caches on
// every step), and a server's wake-up preempting the client thread that was about to send the next server
// its request, leaving that server idle for a whole step. `--cpus` keeps all of a server's threads on the
// given CPUs; `--sched batch` (SCHED_BATCH, sched(7)) tells the kernel not to let its wake-ups preempt a
// running thread. Both are set on the main thread before hadald starts a thread, so every thread it starts
// inherits them, and on every thread already running: libraries may start threads before main (Debian's
// OpenBLAS, when it is the machine's libblas.so.3, starts its pool as it is loaded).
#pragma once

#include <string>
#include <vector>

namespace hadal::app {

// Parses a CPU list as taskset(1) and cpuset(7) write it: "0", "0,2", "1-3,6". Returns the sorted,
// distinct CPU numbers, or an empty vector and a reason in *error.
std::vector<int> parse_cpu_list(const std::string& text, std::string* error);

// "0-1,3": the inverse of parse_cpu_list (for messages).
std::string format_cpu_list(const std::vector<int>& cpus);

// The CPUs this process may run on now (sched_getaffinity(2)).
std::vector<int> allowed_cpus();

// Restricts the calling thread (and the threads it starts later) to `cpus` when non-empty, and switches
// it to SCHED_BATCH when `batch`; with `whole_process`, every other thread of the process now running too
// (those that end meanwhile are skipped). Every CPU must be one the process may run on now. Returns "" or
// the reason it could not.
std::string apply_scheduling(const std::vector<int>& cpus, bool batch, bool whole_process = false);

}  // namespace hadal::app
