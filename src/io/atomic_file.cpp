// Output destinations and input files (io/atomic_file.hpp): atomic replacement of regular files,
// in-place writes to devices and FIFOs, regular-file inputs read with a size bound.
#include "flipflux/io/atomic_file.hpp"

#include <fcntl.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "flipflux/core/error.hpp"

namespace flipflux {
namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& p) {
    return "'" + p.string() + "'";
}

enum class kind { missing, dangling, regular, in_place, refused };

struct destination {
    fs::path path;  ///< the file written: the link's target for a symbolic link
    kind what;
    std::string noun;  ///< "a folder", "a block device", "a socket" for refused kinds
};

/// The descriptor a path names when it is one of this process's own (/dev/stdout, /dev/stderr,
/// /dev/fd/N, /proc/self/fd/N), or -1: those are written through the descriptor itself, at its
/// offset, never reopened (a reopened redirected stdout would start at offset 0) or replaced.
int own_descriptor(const fs::path& path) {
    const std::string p = path.lexically_normal().string();
    if (p == "/dev/stdout") return 1;
    if (p == "/dev/stderr") return 2;
    for (const std::string prefix : {"/dev/fd/", "/proc/self/fd/"})
        if (p.rfind(prefix, 0) == 0 && p.size() > prefix.size() && p.size() - prefix.size() < 8 &&
            p.find_first_not_of("0123456789", prefix.size()) == std::string::npos)
            return std::atoi(p.c_str() + prefix.size());
    return -1;
}

destination classify(const fs::path& path) {
    std::error_code ec;
    if (own_descriptor(path) >= 0) return {path, kind::in_place, {}};
    fs::file_status st = fs::symlink_status(path, ec);
    if (!fs::exists(st)) return {path, kind::missing, {}};
    fs::path target = path;
    if (fs::is_symlink(st)) {
        st = fs::status(path, ec);
        if (!fs::exists(st)) return {path, kind::dangling, "a symbolic link to a missing file"};
        // a device or FIFO is written through the link itself (its target may have no name)
        if (fs::is_character_file(st) || fs::is_fifo(st)) return {path, kind::in_place, {}};
        target = fs::canonical(path, ec);
        if (ec) return {path, kind::dangling, "a symbolic link that cannot be resolved"};
    }
    if (fs::is_regular_file(st)) return {target, kind::regular, {}};
    if (fs::is_character_file(st) || fs::is_fifo(st)) return {target, kind::in_place, {}};
    if (fs::is_directory(st)) return {target, kind::refused, "a folder, not a file"};
    if (fs::is_block_file(st)) return {target, kind::refused, "a block device, not a file"};
    if (fs::is_socket(st)) return {target, kind::refused, "a socket, not a file"};
    return {target, kind::refused, "not a file"};
}

// Writes all of `content` to the descriptor; false with errno set on failure.
bool write_all(int fd, const std::string& content) {
    std::size_t done = 0;
    while (done < content.size()) {
        const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += static_cast<std::size_t>(n);
    }
    return true;
}

// Writes to a device or FIFO in place; a FIFO with no reader is an error, not a wait.
void write_in_place(const fs::path& shown, const fs::path& target, const std::string& content) {
    if (const int own = own_descriptor(target); own >= 0) {
        std::fflush(stdout);  // what was printed before comes first
        if (!write_all(own, content))
            throw output_error("cannot write " + quoted(shown) + ": " + std::strerror(errno));
        return;
    }
    const int fd = ::open(target.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        throw output_error("cannot write " + quoted(shown) + ": " +
                           (err == ENXIO ? std::string("a FIFO with no reader")
                                         : std::string(std::strerror(err))));
    }
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags != -1) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    if (!write_all(fd, content)) {
        const int err = errno;
        ::close(fd);
        throw output_error("cannot write " + quoted(shown) + ": " + std::strerror(err));
    }
    if (::close(fd) != 0 && errno != EINTR)
        throw output_error("cannot write " + quoted(shown) + ": " + std::strerror(errno));
}

void write_replacing(const fs::path& shown, const fs::path& path, const std::string& content) {
    std::error_code ec;
    if (path.has_parent_path()) {
        fs::create_directories(path.parent_path(), ec);
        if (ec)
            throw output_error("cannot write " + quoted(shown) + ": its folder " +
                               quoted(path.parent_path()) + " cannot be created (" + ec.message() +
                               ")");
    }
    const fs::path tmp = path.string() + ".tmp." + std::to_string(::getpid());
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr)
        throw output_error("cannot write " + quoted(shown) + ": " + std::strerror(errno));
    bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size() &&
              std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
    const int err = errno;
    ok = std::fclose(f) == 0 && ok;
    if (!ok) {
        std::remove(tmp.c_str());
        throw output_error("cannot write " + quoted(shown) + ": " + std::strerror(err));
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw output_error("cannot write " + quoted(shown) + ": " + ec.message());
    }
}

// Whether something can be created in the folder: the permission bits do not tell all (root
// passes access() on /proc and on read-only mounts), so a folder is made there and removed.
bool can_create_in(const fs::path& dir) {
    std::string probe = (dir / ".flipflux-probe-XXXXXX").string();
    if (::mkdtemp(probe.data()) == nullptr) return false;
    ::rmdir(probe.c_str());
    return true;
}

// The nearest existing ancestor folder of a new path must be a writable folder, and its names
// within the file system's limits (with room for the temporary name's suffix).
void check_new_path(const fs::path& path, const std::string& field, const std::string& what) {
    if (path.string().size() + 32 >= PATH_MAX)
        throw input_error::about(field, quoted(path) + " is too long a path (PATH_MAX " +
                                            std::to_string(PATH_MAX) + ")");
    for (const fs::path& part : path)
        if (part.string().size() + (part == path.filename() ? 24 : 0) > NAME_MAX)
            throw input_error::about(
                field, quoted(path) + " has a name longer than " + std::to_string(NAME_MAX - 24) +
                           " characters (NAME_MAX " + std::to_string(NAME_MAX) +
                           ", less the room of "
                           "the temporary name)");
    std::error_code ec;
    fs::path dir = path.parent_path();
    while (!dir.empty() && !fs::exists(fs::symlink_status(dir, ec)))
        dir = dir.parent_path();
    if (dir.empty()) dir = ".";
    if (!fs::is_directory(dir, ec))
        throw input_error::about(
            field, quoted(path) + " cannot be " + what + ": " + quoted(dir) + " is not a folder");
    if (::access(dir.c_str(), W_OK | X_OK) != 0 || !can_create_in(dir))
        throw input_error::about(field, quoted(path) + " cannot be " + what + ": the folder " +
                                            quoted(dir) + " is not writable (" +
                                            std::strerror(errno) + ")");
}

}  // namespace

void write_file_atomically(const fs::path& path, const std::string& content) {
    const destination d = classify(path);
    switch (d.what) {
        case kind::missing:
        case kind::regular:
            write_replacing(path, d.path, content);
            return;
        case kind::in_place:
            write_in_place(path, d.path, content);
            return;
        case kind::dangling:
        case kind::refused:
            throw output_error("cannot write " + quoted(path) + ": it is " + d.noun);
    }
}

void check_output_file(const fs::path& path, const std::string& field) {
    if (path.empty()) throw input_error::about(field, "an empty path is not a file");
    const destination d = classify(path);
    switch (d.what) {
        case kind::missing:
            check_new_path(path, field, "written");
            return;
        case kind::regular: {
            const fs::path dir = d.path.has_parent_path() ? d.path.parent_path() : fs::path(".");
            if (::access(d.path.c_str(), W_OK) != 0 || ::access(dir.c_str(), W_OK | X_OK) != 0 ||
                !can_create_in(dir))
                throw input_error::about(
                    field, quoted(path) + " cannot be replaced (" + std::strerror(errno) + ")");
            return;
        }
        case kind::in_place:
            if (::access(d.path.c_str(), W_OK) != 0)
                throw input_error::about(
                    field, quoted(path) + " cannot be written (" + std::strerror(errno) + ")");
            return;
        case kind::dangling:
        case kind::refused:
            throw input_error::about(field, quoted(path) + " is " + d.noun);
    }
}

void check_output_folder(const fs::path& path, const std::string& field) {
    if (path.empty()) throw input_error::about(field, "an empty path is not a folder");
    std::error_code ec;
    if (fs::exists(fs::symlink_status(path, ec))) {
        if (!fs::is_directory(path, ec))
            throw input_error::about(field, quoted(path) + " is not a folder");
        if (::access(path.c_str(), W_OK | X_OK) != 0)
            throw input_error::about(field, "the folder " + quoted(path) + " is not writable (" +
                                                std::strerror(errno) + ")");
        return;
    }
    check_new_path(path, field, "created");
}

std::string read_input_file(const fs::path& path, const std::string& field,
                            std::uintmax_t max_bytes) {
    // a positional file (a candidate CSV) has no field: the message names the file alone
    const auto fail = [&field](const std::string& detail) {
        return field.empty() ? input_error(detail) : input_error::about(field, detail);
    };
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) {
        if (fs::is_symlink(fs::symlink_status(path, ec)))
            throw fail(quoted(path) + " is a symbolic link to a missing file");
        throw fail(quoted(path) + " does not exist");
    }
    if (!fs::is_regular_file(st))
        throw fail(quoted(path) + " is not a regular file (" +
                   (fs::is_directory(st)        ? "a folder"
                    : fs::is_fifo(st)           ? "a FIFO"
                    : fs::is_character_file(st) ? "a character device"
                    : fs::is_block_file(st)     ? "a block device"
                                                : "a socket") +
                   ")");
    // O_NONBLOCK: should the path have become a FIFO since, opening it does not wait for a writer
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw fail(quoted(path) + " cannot be read (" + std::strerror(errno) + ")");
    struct closer {
        int fd;
        ~closer() { ::close(fd); }
    } guard{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode))
        throw fail(quoted(path) + " is not a regular file");
    const std::string bound = std::to_string(max_bytes) + " bytes (docs/limits.md)";
    if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) {
        throw fail(quoted(path) + " has " + std::to_string(info.st_size) +
                   " bytes, more than the bound of " + bound);
    }
    std::string content;
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int err = errno;
            throw fail(quoted(path) + " cannot be read (" + std::strerror(err) + ")");
        }
        if (n == 0) break;
        content.append(buffer, static_cast<std::size_t>(n));
        if (content.size() > max_bytes) {
            throw fail(quoted(path) + " has more than the bound of " + bound);
        }
    }
    return content;
}

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

}  // namespace flipflux
