// Running one of facet's programs from a test, in a child process, as a
// shell would: its output to a log file, a signal sent on cue, and a time
// limit (test_reliability.cpp, test_output.cpp).
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace facet::test {

struct Finished {
    pid_t pid = 0;
    int status = 0;        // as waitpid() gives it
    std::string log;       // stderr and stdout
    double after_signal = 0.0;  // seconds from the signal to the exit
};

// Runs `args` (args[0] is the program) with output to `log_file`; sends
// `signal` once `marker` appears in the output (or at once when marker is
// empty), and waits at most 60 s in all (a test failure past that).
Finished run(const std::vector<std::string>& args, const std::filesystem::path& log_file,
             int signal = 0, const std::string& marker = {});

// How many partial output files ("*.part") a program left in `folder`.
int partial_files(const std::filesystem::path& folder);

}  // namespace facet::test
