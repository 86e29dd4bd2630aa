// An output file that never lies about what it holds (PngWriter writes
// every image through one).
//
// Takes: the path a user gave for an output (-o).
// Gives: a place to write bytes, and commit() once they are all there:
//  - "-" (or /dev/stdout) is standard output, written as the bytes come.
//  - A device or a FIFO (after following links: /dev/null, /dev/tty) is
//    written to where it is, never replaced by a file. A FIFO that no
//    process reads is refused rather than waited on; so is a socket.
//  - Anything else (a new name, a regular file, a link to one) is written
//    beside its target under a name no other writer has,
//    "<target>.<pid>-<n>.part", then flushed to disk and renamed onto the
//    target by commit(). The target holds its old bytes or all of the new
//    ones, never a mix; two processes writing one path each rename their own
//    complete file; a link (or a chain of them) keeps pointing where it did,
//    and one that loops is refused.
// Every error (a folder, no permission, a full disk, a closed pipe) throws
// Error(output_failed) naming the path and the system's cause, and the
// partial file is removed: by the destructor, by an error, and, when a
// signal ends the program, by remove_partial_outputs() (facet/output.hpp;
// it lists 64 at a time). One that a killed process left is found by
// abandoned_partials().
#pragma once

#include <cstddef>
#include <filesystem>

namespace facet {

class OutputFile {
public:
    explicit OutputFile(const std::filesystem::path& path);
    ~OutputFile();  // not committed: removes the partial file
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    void write(const void* data, size_t size);
    // After the last byte: into place (or flushed, for a stream).
    void commit();

    // True when the bytes go to standard output.
    bool is_stream() const { return stream_; }

private:
    [[noreturn]] void fail(const char* doing, int error);
    void discard() noexcept;
    void open_in_place();
    std::filesystem::path link_target(const std::filesystem::path& path);

    std::filesystem::path path_;     // as given, for messages
    std::filesystem::path target_;   // where the bytes end up
    std::filesystem::path partial_;  // empty when written in place
    int fd_ = -1;
    int slot_ = -1;                  // the partial's slot in the signal-time list
    bool stream_ = false;
};

}  // namespace facet
