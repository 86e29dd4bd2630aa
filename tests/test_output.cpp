// Output never lies: facet-render's image reaches where -o names, whole, or
// the run fails saying why, with a file that was there left as it was and
// no partial file left behind. Standard output, devices, FIFOs, links,
// full disks, closed pipes, two writers at once and a killed run's
// leftovers (core/src/base/output_file.hpp). The real facet-render runs in
// a child process.
#include "run_program.hpp"
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/output.hpp>
#include <facet/png.hpp>
#include <facet/texture.hpp>

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace facet;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

#ifdef FACET_RENDER_EXE
// facet-render on the default scene at `size` to `output`, through bash
// when `shell` wraps the command ("{}" stands for it).
test::Finished render(const fs::path& log, const std::string& size, const std::string& output,
                      const std::string& shell = {}) {
    const std::string command = std::string(FACET_RENDER_EXE) + " -q --size " + size + " -o '" +
                                output + "'";
    if (shell.empty()) return test::run({FACET_RENDER_EXE, "-q", "--size", size, "-o", output}, log);
    std::string line = shell;
    line.replace(line.find("{}"), 2, command);
    return test::run({"/bin/bash", "-c", line}, log);
}

int exit_status(const test::Finished& f) { return WIFEXITED(f.status) ? WEXITSTATUS(f.status) : -1; }

int png_width(const fs::path& file) { return load_texture(file, true)->width; }
#endif

}  // namespace

#ifdef FACET_RENDER_EXE

TEST_CASE("an output of - streams the PNG to standard output", "[output]") {
    const test::TempDir dir("output-stream");
    const test::Finished f = render(dir.path / "log.txt", "48x32", "-",
                                    "exec {} > '" + (dir.path / "out.png").string() + "'");
    INFO(f.log);
    CHECK(exit_status(f) == 0);
    CHECK(png_width(dir.path / "out.png") == 48);
}

TEST_CASE("a closed pipe, a full device and a folder are errors with their cause",
          "[output]") {
    const test::TempDir dir("output-errors");
    const fs::path log = dir.path / "log.txt";
    // The reader goes after 8 bytes: EPIPE, not a silent end by SIGPIPE.
    // 2048x2048: the PNG (some 200 KB) is far past the pipe's 64 KiB buffer.
    const test::Finished pipe =
        render(log, "2048x2048", "-", "{} | head -c 8 > /dev/null; exit ${PIPESTATUS[0]}");
    CHECK(exit_status(pipe) == 1);
    CHECK_THAT(pipe.log, Contains("standard output") && Contains("Broken pipe"));
    const test::Finished full = render(log, "64x64", "/dev/full");
    CHECK(exit_status(full) == 1);
    CHECK_THAT(full.log, Contains("/dev/full") && Contains("No space left on device"));
    // A folder is refused, named.
    const test::Finished folder = render(log, "64x64", dir.path.string());
    CHECK(exit_status(folder) == 1);
    CHECK_THAT(folder.log, Contains("it is a folder"));
}

#endif  // FACET_RENDER_EXE

TEST_CASE("a write that fails midway leaves the earlier image as it was", "[output]") {
    // In a child whose files may not grow past 4 KiB (RLIMIT_FSIZE, with
    // SIGXFSZ ignored as facet's programs do): a noise image's PNG is far
    // larger, so its write fails with EFBIG partway through.
    const test::TempDir dir("output-limit");
    const fs::path old = dir.write("old.png", "the bytes of an earlier image");
    std::vector<uint8_t> noise(size_t(128) * 128 * 4);
    std::mt19937 random(5);
    for (uint8_t& byte : noise) byte = uint8_t(random());
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        const rlimit small{4096, 4096};
        setrlimit(RLIMIT_FSIZE, &small);
        std::signal(SIGXFSZ, SIG_IGN);
        try {
            write_png_rows(old, noise.data(), 128 * 4, 128, 128, 1);
        } catch (const Error& e) {
            _exit(std::string(e.what()).find("File too large") != std::string::npos ? 3 : 4);
        }
        _exit(0);
    }
    int status = 0;
    waitpid(child, &status, 0);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 3);  // the error, with its cause
    CHECK(test::read_file(old) == "the bytes of an earlier image");
    CHECK(test::partial_files(dir.path) == 0);
}

#ifdef FACET_RENDER_EXE

TEST_CASE("devices, FIFOs and links are written through, never replaced", "[output]") {
    const test::TempDir dir("output-special");
    const fs::path log = dir.path / "log.txt";
    CHECK(exit_status(render(log, "64x64", "/dev/null")) == 0);
    CHECK(fs::is_character_file("/dev/null"));
    // A FIFO: refused at once while no one reads it, written when one does.
    const fs::path fifo = dir.path / "fifo.png";
    REQUIRE(mkfifo(fifo.c_str(), 0644) == 0);
    const test::Finished alone = render(log, "64x64", fifo.string());
    CHECK(exit_status(alone) == 1);
    CHECK_THAT(alone.log, Contains("no process reads the FIFO"));
    const fs::path read_back = dir.path / "from-fifo.png";
    std::thread reader([&] { std::ofstream(read_back, std::ios::binary) << test::read_file(fifo); });
    // The reader opens the FIFO before the writer looks for one.
    bool written = false;
    for (int i = 0; i < 500 && !written; ++i) {
        written = exit_status(render(log, "40x24", fifo.string())) == 0;
        if (!written) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!written) {  // the reader still waits: an open and close ends its read
        const int fd = open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
        if (fd >= 0) close(fd);
    }
    reader.join();
    CHECK(written);
    CHECK(fs::is_fifo(fifo));
    CHECK(png_width(read_back) == 40);
    // A link to a file: the file gets the image, the link stays a link.
    const fs::path target = dir.write("real/target.png", "old");
    const fs::path link = dir.path / "link.png";
    fs::create_symlink(target, link);
    CHECK(exit_status(render(log, "56x24", link.string())) == 0);
    CHECK(fs::is_symlink(link));
    CHECK(png_width(target) == 56);
    CHECK(test::partial_files(dir.path / "real") == 0);
    // A link to a file not there yet: made where the link points.
    fs::create_symlink(dir.path / "real" / "new.png", dir.path / "ahead.png");
    CHECK(exit_status(render(log, "24x24", (dir.path / "ahead.png").string())) == 0);
    CHECK(fs::is_symlink(dir.path / "ahead.png"));
    CHECK(png_width(dir.path / "real" / "new.png") == 24);
    // Links that loop: refused, named.
    fs::create_symlink(dir.path / "loop-b.png", dir.path / "loop-a.png");
    fs::create_symlink(dir.path / "loop-a.png", dir.path / "loop-b.png");
    const test::Finished loop = render(log, "24x24", (dir.path / "loop-a.png").string());
    CHECK(exit_status(loop) == 1);
    CHECK_THAT(loop.log, Contains("its links loop"));
}

TEST_CASE("two renders to one path each write a whole image of their own", "[output]") {
    const test::TempDir dir("output-race");
    const std::string out = (dir.path / "out.png").string();
    const std::string exe = FACET_RENDER_EXE;
    // Both at once; the shell's status is the first's and the second's.
    const std::string both = exe + " -q --size 320x200 -o '" + out + "' & " + exe +
                             " -q --size 200x320 -o '" + out + "'; b=$?; wait $!; a=$?; " +
                             "exit $((a * 16 + b))";
    for (int round = 0; round < 3; ++round) {
        const test::Finished f = test::run({"/bin/bash", "-c", both}, dir.path / "log.txt");
        INFO(f.log);
        CHECK(exit_status(f) == 0);
        const int width = png_width(out);  // whole: it decodes
        CHECK((width == 320 || width == 200));
        CHECK(test::partial_files(dir.path) == 0);
    }
}

TEST_CASE("resuming a sequence removes the partial files of a run that was killed", "[output]") {
    const test::TempDir dir("output-resume");
    const pid_t dead = fork();  // a process id that no longer runs
    if (dead == 0) _exit(0);
    waitpid(dead, nullptr, 0);
    const fs::path left = dir.write("frame_0001.png." + std::to_string(dead) + "-0.part", "half");
    const fs::path running =  // this process runs: its file is not abandoned
        dir.write("frame_0000.png." + std::to_string(getpid()) + "-7.part", "busy");
    // As a user types it: a pattern relative to the working folder.
    const test::Finished f =
        test::run({"/bin/bash", "-c",
                   "cd '" + dir.path.string() + "' && exec " + FACET_RENDER_EXE +
                       " --size 32x32 --frames 0..1 --resume -o frame_%04d.png"},
                  dir.path / "log.txt");
    INFO(f.log);
    CHECK(exit_status(f) == 0);
    CHECK_FALSE(fs::exists(left));
    CHECK_THAT(f.log, Contains("which a stopped run left unfinished"));
    CHECK(fs::exists(running));
    CHECK(png_width(dir.path / "frame_0001.png") == 32);
}

#endif  // FACET_RENDER_EXE

TEST_CASE("a partial file whose process has exited but is not reaped is abandoned", "[output]") {
    // A zombie: it exists until its parent waits for it (in a container
    // whose first process reaps no one, for good), yet can finish nothing.
    const test::TempDir dir("output-zombie");
    const pid_t zombie = fork();
    if (zombie == 0) _exit(0);
    for (int i = 0; i < 200 && kill(zombie, 0) == 0; ++i) {  // until it has exited
        std::ifstream stat("/proc/" + std::to_string(zombie) + "/stat");
        std::string line;
        std::getline(stat, line);
        if (line.find(") Z") != std::string::npos) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const fs::path left = dir.write("out.png." + std::to_string(zombie) + "-0.part", "half");
    CHECK(remove_abandoned_partials(dir.path / "out.png") == 1);
    CHECK_FALSE(fs::exists(left));
    waitpid(zombie, nullptr, 0);
}
