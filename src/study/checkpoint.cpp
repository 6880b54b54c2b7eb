// Checkpoints of Monte Carlo studies (include/flipflux/study/checkpoint.hpp).
#include "flipflux/study/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <limits>
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

}  // namespace

std::string trajectory_record(std::size_t energy, const trajectory_result& r) {
    std::string s = "T";
    put_int(s, energy);
    put_int(s, r.index);
    put_int(s, static_cast<int>(r.status));
    put(s, r.end_time);
    put(s, r.max_energy_drift);
    put(s, r.lyapunov);
    put_int(s, r.chaotic ? 1 : 0);
    put_int(s, r.steps);
    put_int(s, r.rejected_steps);
    put_int(s, r.evaluations);
    put_int(s, r.energy_check_rejections);
    for (double x : r.initial_state)
        put(s, x);
    put_int(s, r.crossing_times.size());
    for (const std::vector<double>& times : r.crossing_times) {
        put_int(s, times.size());
        for (double t : times)
            put(s, t);
    }
    return hashed_line(s);
}

trajectory_result parse_trajectory_record(std::string_view line, std::size_t criteria,
                                          std::size_t& energy) {
    std::string_view content;
    if (!verified(line, content)) throw std::runtime_error("damaged record (hash mismatch)");
    tokens t(content);
    if (t.next() != "T") throw std::runtime_error("not a trajectory record");
    trajectory_result r;
    energy = t.integer<std::size_t>();
    r.index = t.integer<std::uint64_t>();
    const int status = t.integer<int>();
    if (status < 0 || status > static_cast<int>(rk_status::non_finite))
        throw std::runtime_error("bad status " + std::to_string(status));
    r.status = static_cast<rk_status>(status);
    r.end_time = t.real();
    r.max_energy_drift = t.real();
    r.lyapunov = t.real();
    r.chaotic = t.integer<int>() != 0;
    r.steps = t.integer<long>();
    r.rejected_steps = t.integer<long>();
    r.evaluations = t.integer<long>();
    r.energy_check_rejections = t.integer<long>();
    for (double& x : r.initial_state)
        x = t.real();
    const auto nc = t.integer<std::size_t>();
    if (nc != criteria)
        throw std::runtime_error("the record has " + std::to_string(nc) + " criteria, not " +
                                 std::to_string(criteria));
    r.crossing_times.resize(nc);
    for (std::vector<double>& times : r.crossing_times) {
        const auto n = t.integer<std::size_t>();
        if (n > content.size()) throw std::runtime_error("bad crossing count");
        times.resize(n);
        for (double& x : times)
            x = t.real();
    }
    if (!t.done()) throw std::runtime_error("trailing fields");
    return r;
}

namespace {

void put_summary(std::string& s, const summary_statistics& x) {
    put_int(s, x.count);
    put(s, x.mean);
    put(s, x.standard_deviation);
    put(s, x.standard_error);
    put(s, x.minimum);
    put(s, x.maximum);
    put(s, x.skewness);
    put(s, x.kurtosis);
}

summary_statistics get_summary(tokens& t) {
    summary_statistics x;
    x.count = t.integer<std::size_t>();
    x.mean = t.real();
    x.standard_deviation = t.real();
    x.standard_error = t.real();
    x.minimum = t.real();
    x.maximum = t.real();
    x.skewness = t.real();
    x.kurtosis = t.real();
    return x;
}

void put_histogram(std::string& s, const histogram& h) {
    put(s, h.lower);
    put(s, h.upper);
    put_int(s, h.underflow);
    put_int(s, h.overflow);
    put_int(s, h.counts.size());
    for (std::uint64_t n : h.counts)
        put_int(s, n);
}

histogram get_histogram(tokens& t, std::size_t limit) {
    histogram h;
    h.lower = t.real();
    h.upper = t.real();
    h.underflow = t.integer<std::uint64_t>();
    h.overflow = t.integer<std::uint64_t>();
    const auto n = t.integer<std::size_t>();
    if (n > limit) throw std::runtime_error("bad bin count");
    h.counts.resize(n);
    for (std::uint64_t& c : h.counts)
        c = t.integer<std::uint64_t>();
    return h;
}

void put_counts(std::string& s, const flip_count_statistics& x) {
    put_int(s, x.fano.size());
    for (const window_fano& f : x.fano) {
        put(s, f.window);
        put_int(s, f.windows);
        put_int(s, f.windows_chaotic);
        put(s, f.mean_count);
        put(s, f.fano);
        put(s, f.mean_count_chaotic);
        put(s, f.fano_chaotic);
    }
    put(s, x.cv2);
    put(s, x.cv2_chaotic);
    put_int(s, x.survival.size());
    for (const auto& p : x.survival) {
        put(s, p.time);
        put(s, p.survival);
        put(s, p.survival_chaotic);
    }
}

flip_count_statistics get_counts(tokens& t, std::size_t limit) {
    flip_count_statistics x;
    const auto n = t.integer<std::size_t>();
    if (n > limit) throw std::runtime_error("bad window count");
    x.fano.resize(n);
    for (window_fano& f : x.fano) {
        f.window = t.real();
        f.windows = t.integer<std::uint64_t>();
        f.windows_chaotic = t.integer<std::uint64_t>();
        f.mean_count = t.real();
        f.fano = t.real();
        f.mean_count_chaotic = t.real();
        f.fano_chaotic = t.real();
    }
    x.cv2 = t.real();
    x.cv2_chaotic = t.real();
    const auto m = t.integer<std::size_t>();
    if (m > limit) throw std::runtime_error("bad tail count");
    x.survival.resize(m);
    for (auto& p : x.survival) {
        p.time = t.real();
        p.survival = t.real();
        p.survival_chaotic = t.real();
    }
    return x;
}

}  // namespace

std::string energy_record(std::size_t energy, const energy_result& e) {
    std::string s = "E";
    put_int(s, energy);
    put(s, e.seconds);
    put_int(s, e.threads);
    put_int(s, e.processes);
    put(s, e.steps_per_trajectory);
    put_int(s, e.failed_trajectories);
    put_int(s, e.energy_check_rejections);
    put(s, e.max_energy_drift);
    put_int(s, e.criteria.size());
    for (const criterion_result& c : e.criteria) {
        const criterion_statistics& x = c.statistics;
        put(s, x.predicted_rate);
        put_int(s, x.flips);
        put_summary(s, x.rates);
        put(s, x.z_score);
        put_int(s, x.chaotic);
        put(s, x.chaotic_fraction);
        put_summary(s, x.chaotic_rates);
        put(s, x.chaotic_z_score);
        put_summary(s, x.residence.summary);
        put(s, x.residence.q001);
        put(s, x.residence.q01);
        put(s, x.residence.median);
        put_histogram(s, x.residence.distribution);
        put_histogram(s, x.rate_distribution);
        put_int(s, x.replicate_rates.size());
        for (std::size_t k = 0; k < x.replicate_rates.size(); ++k) {
            put_summary(s, x.replicate_rates[k]);
            put_summary(s, x.replicate_chaotic_rates[k]);
        }
        put_counts(s, x.counts);
    }
    put_int(s, e.paired.size());
    for (const paired_difference& d : e.paired) {
        put_int(s, d.first);
        put_int(s, d.second);
        put_summary(s, d.difference);
    }
    put(s, e.cpu_seconds);  // last: the records before it was recorded end at the pairs
    return hashed_line(s);
}

energy_result parse_energy_record(std::string_view line, std::size_t criteria,
                                  std::size_t& energy) {
    std::string_view content;
    if (!verified(line, content)) throw std::runtime_error("damaged record (hash mismatch)");
    tokens t(content);
    if (t.next() != "E") throw std::runtime_error("not an energy record");
    energy_result e;
    energy = t.integer<std::size_t>();
    e.seconds = t.real();
    e.threads = t.integer<int>();
    e.processes = t.integer<int>();
    e.steps_per_trajectory = t.real();
    e.failed_trajectories = t.integer<std::uint64_t>();
    e.energy_check_rejections = t.integer<std::int64_t>();
    e.max_energy_drift = t.real();
    const auto nc = t.integer<std::size_t>();
    if (nc != criteria)
        throw std::runtime_error("the record has " + std::to_string(nc) + " criteria, not " +
                                 std::to_string(criteria));
    e.criteria.resize(nc);
    for (criterion_result& c : e.criteria) {
        criterion_statistics& x = c.statistics;
        x.predicted_rate = t.real();
        x.flips = t.integer<std::uint64_t>();
        x.rates = get_summary(t);
        x.z_score = t.real();
        x.chaotic = t.integer<std::size_t>();
        x.chaotic_fraction = t.real();
        x.chaotic_rates = get_summary(t);
        x.chaotic_z_score = t.real();
        x.residence.summary = get_summary(t);
        x.residence.q001 = t.real();
        x.residence.q01 = t.real();
        x.residence.median = t.real();
        x.residence.distribution = get_histogram(t, content.size());
        x.rate_distribution = get_histogram(t, content.size());
        const auto replicates = t.integer<std::size_t>();
        if (replicates > content.size()) throw std::runtime_error("bad replicate count");
        for (std::size_t k = 0; k < replicates; ++k) {
            x.replicate_rates.push_back(get_summary(t));
            x.replicate_chaotic_rates.push_back(get_summary(t));
        }
        x.counts = get_counts(t, content.size());
    }
    const auto pairs = t.integer<std::size_t>();
    if (pairs != criteria * (criteria - 1) / 2) throw std::runtime_error("bad pair count");
    e.paired.resize(pairs);
    for (paired_difference& d : e.paired) {
        d.first = t.integer<std::size_t>();
        d.second = t.integer<std::size_t>();
        if (!(d.first < d.second && d.second < criteria))
            throw std::runtime_error("bad criterion pair");
        d.difference = get_summary(t);
    }
    e.cpu_seconds = t.done() ? std::numeric_limits<double>::quiet_NaN() : t.real();
    if (!t.done()) throw std::runtime_error("trailing fields");
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
                                     const checkpoint_content& content, double interval_seconds)
    : file_(std::move(file)),
      header_line_(hashed_line(std::string(header_tag) + header.dump())),
      interval_(interval_seconds),
      last_flush_(std::chrono::steady_clock::now()) {
    for (const auto& [k, done] : content.completed)
        completed_lines_ += energy_record(k, done);
    std::string tail;
    for (const auto& [k, trajectories] : content.trajectories)
        for (const auto& [index, r] : trajectories) {
            tail += trajectory_record(k, r);
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
