// Checkpoints of Monte Carlo studies (include/flipflux/study/checkpoint.hpp).
#include "flipflux/study/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/io/atomic_file.hpp"

namespace flipflux {
namespace {

using json = nlohmann::ordered_json;

constexpr std::string_view header_tag = "flipflux-checkpoint ";

std::string hashed_line(const std::string& content) {
    return content + " #" + checksum_hex(content) + "\n";
}

// The content of a hashed line (without the newline), or false when the hash does not match.
bool verified(std::string_view line, std::string_view& content) {
    if (line.size() < 18) return false;
    const std::string_view tail = line.substr(line.size() - 18);
    if (tail[0] != ' ' || tail[1] != '#') return false;
    content = line.substr(0, line.size() - 18);
    return checksum_hex(content) == tail.substr(2);
}

void put(std::string& s, double x) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    s += ' ';
    s.append(buf, r.ptr);
}
template <class Int>
void put_int(std::string& s, Int x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    s += ' ';
    s.append(buf, r.ptr);
}

class tokens {
  public:
    explicit tokens(std::string_view s) : s_(s) {}
    std::string_view next() {
        while (pos_ < s_.size() && s_[pos_] == ' ')
            ++pos_;
        if (pos_ >= s_.size()) throw std::runtime_error("the record ends early");
        const std::size_t end = std::min(s_.find(' ', pos_), s_.size());
        const std::string_view t = s_.substr(pos_, end - pos_);
        pos_ = end;
        return t;
    }
    double real() {
        const std::string_view t = next();
        double v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size())
            throw std::runtime_error("'" + std::string(t) + "' is not a number");
        return v;
    }
    template <class Int>
    Int integer() {
        const std::string_view t = next();
        Int v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size())
            throw std::runtime_error("'" + std::string(t) + "' is not an integer");
        return v;
    }
    bool done() {
        while (pos_ < s_.size() && s_[pos_] == ' ')
            ++pos_;
        return pos_ >= s_.size();
    }

  private:
    std::string_view s_;
    std::size_t pos_ = 0;
};

std::string shorten(const std::string& s) {
    return s.size() <= 60 ? s : s.substr(0, 57) + "...";
}

// One field list per record drives both directions: each `*_fields(io, x)` below names the fields
// in their order once, and is run with a record_writer (x const: the line is built) or a
// record_reader (the line's tokens parsed into x, each count checked against its bound).

/// Builds a record: its tag, then each field as a space and its shortest round-trip text.
class record_writer {
  public:
    explicit record_writer(const char* tag) : s_(tag) {}
    void real(const double& x) { put(s_, x); }
    template <class Int>
    void integer(const Int& x) {
        put_int(s_, x);
    }
    /// A count of items that follow (written as is; `bound` and `what` serve the reader).
    std::size_t count(std::size_t n, std::size_t /*bound*/, const char* /*what*/) {
        put_int(s_, n);
        return n;
    }
    /// A vector's size, then its items by `each`.
    template <class V, class F>
    void sequence(V& v, std::size_t bound, const char* what, F each) {
        count(v.size(), bound, what);
        for (auto& x : v)
            each(x);
    }
    static constexpr bool reading = false;
    std::string line() const { return hashed_line(s_); }

  private:
    std::string s_;
};

/// Parses a record written by record_writer through the same field list.
class record_reader {
  public:
    /// The verified content of `line` (its hash checked), which must start with `tag` (else
    /// `wrong_tag` is the error).
    record_reader(std::string_view line, std::string_view tag, const char* wrong_tag) {
        if (!verified(line, content_)) throw std::runtime_error("damaged record (hash mismatch)");
        t_.emplace(content_);
        if (t_->next() != tag) throw std::runtime_error(wrong_tag);
    }
    void real(double& x) { x = t_->real(); }
    template <class Int>
    void integer(Int& x) {
        x = t_->template integer<Int>();
    }
    /// A count, at most `bound` (else "bad <what>"; a bound of 0 means the line's length).
    std::size_t count(std::size_t /*written*/, std::size_t bound, const char* what) {
        const auto n = t_->integer<std::size_t>();
        if (n > (bound ? bound : content_.size()))
            throw std::runtime_error(std::string("bad ") + what);
        return n;
    }
    template <class V, class F>
    void sequence(V& v, std::size_t bound, const char* what, F each) {
        v.resize(count(0, bound, what));
        for (auto& x : v)
            each(x);
    }
    static constexpr bool reading = true;
    bool done() { return t_->done(); }

  private:
    std::string_view content_;
    std::optional<tokens> t_;
};

/// A record's criteria count: written as is; read, it must be the layout's.
template <class Io>
std::size_t criteria_count(Io& io, std::size_t n, std::size_t criteria) {
    const std::size_t got = io.count(n, std::numeric_limits<std::size_t>::max(), "criteria");
    if (Io::reading && got != criteria)
        throw std::runtime_error("the record has " + std::to_string(got) + " criteria, not " +
                                 std::to_string(criteria));
    return got;
}

/// A trajectory (the T record after its energy). `chaotic`: the classification, written for the
/// readers of older versions and ignored when read (it is computed: ensemble_result::chaotic).
template <class Io, class R>
void trajectory_fields(Io& io, R& r, std::size_t criteria, int& chaotic) {
    io.integer(r.index);
    int status = static_cast<int>(r.status);
    io.integer(status);
    if constexpr (Io::reading) {
        if (status < 0 || status > static_cast<int>(rk_status::non_finite))
            throw std::runtime_error("bad status " + std::to_string(status));
        r.status = static_cast<rk_status>(status);
    }
    io.real(r.end_time);
    io.real(r.max_energy_drift);
    io.real(r.lyapunov);
    io.integer(chaotic);
    io.integer(r.steps);
    io.integer(r.rejected_steps);
    io.integer(r.evaluations);
    io.integer(r.energy_check_rejections);
    for (auto& x : r.initial_state)
        io.real(x);
    const std::size_t nc = criteria_count(io, r.crossing_times.size(), criteria);
    if constexpr (Io::reading) r.crossing_times.resize(nc);
    for (auto& times : r.crossing_times)
        io.sequence(times, 0, "crossing count", [&](auto& t) { io.real(t); });
}

template <class Io, class S>
void summary_fields(Io& io, S& x) {
    io.integer(x.count);
    io.real(x.mean);
    io.real(x.standard_deviation);
    io.real(x.standard_error);
    io.real(x.minimum);
    io.real(x.maximum);
    io.real(x.skewness);
    io.real(x.kurtosis);
}

template <class Io, class H>
void histogram_fields(Io& io, H& h) {
    io.real(h.lower);
    io.real(h.upper);
    io.integer(h.underflow);
    io.integer(h.overflow);
    io.sequence(h.counts, 0, "bin count", [&](auto& n) { io.integer(n); });
}

template <class Io, class C>
void counts_fields(Io& io, C& x) {
    io.sequence(x.fano, 0, "window count", [&](auto& f) {
        io.real(f.window);
        io.integer(f.windows);
        io.integer(f.windows_chaotic);
        io.real(f.mean_count);
        io.real(f.fano);
        io.real(f.mean_count_chaotic);
        io.real(f.fano_chaotic);
    });
    io.real(x.cv2);
    io.real(x.cv2_chaotic);
    io.sequence(x.survival, 0, "tail count", [&](auto& p) {
        io.real(p.time);
        io.real(p.survival);
        io.real(p.survival_chaotic);
    });
}

template <class Io, class X>
void criterion_fields(Io& io, X& x) {
    io.real(x.predicted_rate);
    io.integer(x.flips);
    summary_fields(io, x.rates);
    io.real(x.z_score);
    io.integer(x.chaotic);
    io.real(x.chaotic_fraction);
    summary_fields(io, x.chaotic_rates);
    io.real(x.chaotic_z_score);
    summary_fields(io, x.residence.summary);
    io.real(x.residence.q001);
    io.real(x.residence.q01);
    io.real(x.residence.median);
    histogram_fields(io, x.residence.distribution);
    histogram_fields(io, x.rate_distribution);
    // the replicates' summaries, pooled and chaotic, in pairs
    const std::size_t replicates = io.count(x.replicate_rates.size(), 0, "replicate count");
    if constexpr (Io::reading) {
        x.replicate_rates.resize(replicates);
        x.replicate_chaotic_rates.resize(replicates);
    }
    for (std::size_t k = 0; k < replicates; ++k) {
        summary_fields(io, x.replicate_rates[k]);
        summary_fields(io, x.replicate_chaotic_rates[k]);
    }
    counts_fields(io, x.counts);
}

/// An energy's statistics (the E record after its energy). cpu_seconds comes last: records
/// written before it was recorded end at the pairs (read as NaN).
template <class Io, class E>
void energy_fields(Io& io, E& e, std::size_t criteria) {
    io.real(e.seconds);
    io.integer(e.threads);
    io.integer(e.processes);
    io.real(e.steps_per_trajectory);
    io.integer(e.failed_trajectories);
    io.integer(e.energy_check_rejections);
    io.real(e.max_energy_drift);
    const std::size_t nc = criteria_count(io, e.criteria.size(), criteria);
    if constexpr (Io::reading) e.criteria.resize(nc);
    for (auto& c : e.criteria)
        criterion_fields(io, c.statistics);
    const std::size_t pairs =
        io.count(e.paired.size(), std::numeric_limits<std::size_t>::max(), "pair count");
    if (Io::reading && pairs != criteria * (criteria - 1) / 2)
        throw std::runtime_error("bad pair count");
    if constexpr (Io::reading) e.paired.resize(pairs);
    for (auto& d : e.paired) {
        io.integer(d.first);
        io.integer(d.second);
        if (Io::reading && !(d.first < d.second && d.second < criteria))
            throw std::runtime_error("bad criterion pair");
        summary_fields(io, d.difference);
    }
    if constexpr (Io::reading) {
        if (io.done()) {
            e.cpu_seconds = std::numeric_limits<double>::quiet_NaN();
            return;
        }
    }
    io.real(e.cpu_seconds);
}

}  // namespace

std::string trajectory_record(std::size_t energy, const trajectory_result& r, bool chaotic) {
    record_writer w("T");
    w.integer(energy);
    int flag = chaotic ? 1 : 0;
    trajectory_fields(w, r, r.crossing_times.size(), flag);
    return w.line();
}

trajectory_result parse_trajectory_record(std::string_view line, std::size_t criteria,
                                          std::size_t& energy) {
    record_reader io(line, "T", "not a trajectory record");
    trajectory_result r;
    io.integer(energy);
    int chaotic = 0;  // computed from lyapunov by the ensemble's rule, not read
    trajectory_fields(io, r, criteria, chaotic);
    if (!io.done()) throw std::runtime_error("trailing fields");
    return r;
}

std::string energy_record(std::size_t energy, const energy_result& e) {
    record_writer w("E");
    w.integer(energy);
    energy_fields(w, e, e.criteria.size());
    return w.line();
}

energy_result parse_energy_record(std::string_view line, std::size_t criteria,
                                  std::size_t& energy) {
    record_reader io(line, "E", "not an energy record");
    energy_result e;
    io.integer(energy);
    energy_fields(io, e, criteria);
    if (!io.done()) throw std::runtime_error("trailing fields");
    return e;
}

std::string read_checkpoint_text(const std::filesystem::path& file, bool& exists) {
    std::error_code ec;
    exists = std::filesystem::exists(file, ec);
    if (!exists) return {};
    // bounded by the memory a request may hold, not by the 256 MiB of other inputs: a checkpoint
    // this program wrote (every crossing time of every trajectory) may be larger
    return read_input_file(file, "checkpoint",
                           static_cast<std::uintmax_t>(std::max(memory_budget_bytes(), 0.0)));
}

checkpoint_layout checkpoint_layout::single(std::size_t energies, std::size_t criteria) {
    checkpoint_layout l;
    l.trajectory_criteria.assign(energies, criteria);
    l.energy_criteria.assign(energies, criteria);
    return l;
}

checkpoint_content parse_checkpoint(const std::string& text, const json& header,
                                    std::size_t criteria, const std::filesystem::path& file) {
    const auto it = header.find("energies");
    return parse_checkpoint(
        text, header, checkpoint_layout::single(it == header.end() ? 0 : it->size(), criteria),
        file);
}

checkpoint_content parse_checkpoint(const std::string& text, const json& header,
                                    const checkpoint_layout& layout,
                                    const std::filesystem::path& file) {
    checkpoint_content c;
    c.exists = true;
    const std::string name = "'" + file.string() + "'";
    // split into lines; a last line without newline is torn
    std::vector<std::string_view> lines;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) {
            c.torn = true;
            break;
        }
        lines.emplace_back(text.data() + pos, nl - pos);
        pos = nl + 1;
    }
    std::string_view content;
    if (lines.empty() || !verified(lines[0], content) || !content.starts_with(header_tag))
        throw input_error::about("checkpoint",
                                 name + " is not a flipflux checkpoint (no valid header line)");
    json found;
    try {
        found = json::parse(content.substr(header_tag.size()));
    } catch (const json::exception&) {
        throw input_error::about("checkpoint",
                                 name + " is not a flipflux checkpoint (unreadable header)");
    }
    if (!found.is_object())
        throw input_error::about("checkpoint", name + " is not a flipflux checkpoint");
    for (const auto& [key, value] : header.items()) {
        const auto it = found.find(key);
        const std::string theirs = it == found.end() ? "(absent)" : it->dump();
        if (it == found.end() || *it != value)
            throw input_error::about("checkpoint", name + " belongs to another run: its " + key +
                                                       " is " + shorten(theirs) +
                                                       ", this run's is " + shorten(value.dump()));
    }
    for (const auto& [key, value] : found.items())
        if (!header.contains(key))
            throw input_error::about("checkpoint", name +
                                                       " belongs to another run: it has a field " +
                                                       key + " this run does not have");
    const std::size_t energies = layout.trajectory_criteria.size();
    // the record's energy (or slot) index, before its fields are parsed against its criteria
    const auto index_of = [](std::string_view line) {
        std::size_t k = 0;
        const std::size_t from = std::min<std::size_t>(2, line.size());
        const auto r = std::from_chars(line.data() + from, line.data() + line.size(), k);
        if (r.ec != std::errc() || line.size() < 2 || line[1] != ' ')
            throw std::runtime_error("no energy index");
        return k;
    };
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const bool last = i + 1 == lines.size();
        try {
            if (!lines[i].empty() && lines[i][0] == 'T') {
                std::size_t k = index_of(lines[i]);
                if (k >= energies) throw std::runtime_error("energy index out of range");
                trajectory_result r =
                    parse_trajectory_record(lines[i], layout.trajectory_criteria[k], k);
                const std::uint64_t index = r.index;
                c.trajectories[k][index] = std::move(r);
            } else {
                std::size_t k = index_of(lines[i]);
                if (k >= layout.energy_criteria.size() || layout.energy_criteria[k] == 0)
                    throw std::runtime_error("energy index out of range");
                energy_result e = parse_energy_record(lines[i], layout.energy_criteria[k], k);
                c.completed[k] = std::move(e);
            }
        } catch (const std::exception& e) {
            if (last) {  // a torn or damaged last line: the run was killed while writing it
                c.torn = true;
                break;
            }
            throw input_error::about(
                "checkpoint",
                name + " is damaged (line " + std::to_string(i + 1) + ": " + e.what() + ")");
        }
    }
    for (const auto& [slot, done] : c.completed)
        c.trajectories.erase(slot / std::max<std::size_t>(layout.studies, 1));
    return c;
}

checkpoint_writer::checkpoint_writer(std::filesystem::path file, const json& header,
                                     const checkpoint_content& content, double interval_seconds,
                                     const std::function<bool(const trajectory_result&)>& chaotic)
    : file_(std::move(file)),
      header_line_(hashed_line(std::string(header_tag) + header.dump())),
      interval_(interval_seconds),
      last_flush_(std::chrono::steady_clock::now()) {
    for (const auto& [k, done] : content.completed)
        completed_lines_ += energy_record(k, done);
    std::string tail;
    for (const auto& [k, trajectories] : content.trajectories)
        for (const auto& [index, r] : trajectories) {
            tail += trajectory_record(k, r, chaotic && chaotic(r));
            ++saved_;
        }
    rewrite(tail);
}

checkpoint_writer::~checkpoint_writer() {
    if (fd_ >= 0) ::close(fd_);
}

void checkpoint_writer::rewrite(const std::string& tail) {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    write_file_atomically(file_, header_line_ + completed_lines_ + tail);  // output_error
    open_for_append();
}

void checkpoint_writer::open_for_append() {
    fd_ = ::open(file_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd_ < 0)
        throw input_error::about("checkpoint", "cannot append to '" + file_.string() + "'");
}

void checkpoint_writer::add(std::string line) {
    pending_ += line;
    ++saved_;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - last_flush_).count() >=
        interval_)
        flush();
}

void checkpoint_writer::flush() {
    last_flush_ = std::chrono::steady_clock::now();
    std::size_t done = 0;
    while (done < pending_.size()) {
        const ssize_t n = ::write(fd_, pending_.data() + done, pending_.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw std::runtime_error("checkpoint: cannot append to '" + file_.string() +
                                     "': " + std::strerror(errno));
        }
        done += static_cast<std::size_t>(n);
    }
    pending_.clear();
    ::fdatasync(fd_);
}

void checkpoint_writer::complete(std::size_t energy, const energy_result& done) {
    complete({{energy, &done}});
}

void checkpoint_writer::complete(
    const std::vector<std::pair<std::size_t, const energy_result*>>& slots) {
    flush();
    for (const auto& [slot, done] : slots)
        completed_lines_ += energy_record(slot, *done);
    saved_ = 0;
    rewrite("");
}

}  // namespace flipflux
