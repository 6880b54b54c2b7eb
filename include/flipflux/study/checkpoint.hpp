// Checkpoints of a Monte Carlo study (`flipflux simulate --checkpoint FILE`), and the text form
// of one trajectory's result that checkpoints and the MPI gather share.
//
// File format (text, one record per line; every line ends with " #" and the FNV-1a 64-bit hash
// of what precedes it, in 16 hex digits, so a torn or damaged line is recognised):
//   line 1   "flipflux-checkpoint <json>"  the run's identity: format, flipflux version, model,
//            arm, criteria, energies, trajectories, first index, time, seed, method, tolerances,
//            chaos options, bins, estimator (everything the results depend on);
//   "E <k> <fields>"  energy k completed: its statistics (energy_record);
//   "T <k> <fields>"  one finished trajectory of energy k (trajectory_record).
// A run of several studies on one set of trajectories (study/simulation.hpp) numbers its energies
// k over the union of the studies' energies; its T records carry the crossings of every criterion
// counted at energy k (all studies'), and its E records are per study: "E <k * studies + p>" for
// study p, the E records of one energy written together (checkpoint_layout).
// Real numbers are written by std::to_chars in the shortest form that reads back to the same
// double (std::from_chars), so a resumed run reproduces every bit of an uninterrupted one.
// A run appends T lines as trajectories finish (write(2) of whole lines, fdatasync, at most
// every `interval` seconds), and when an energy completes rewrites the file atomically
// (write_file_atomically) as the header plus the E lines: the file stays small. A SIGKILL can
// only leave a torn last line, which reading drops; a damaged line before the last makes the file
// unreadable (refused).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/io/checksum.hpp"
#include "flipflux/study/study_result.hpp"

namespace flipflux {

inline constexpr int checkpoint_format_version = 4;

/// One line (with its hash and the newline) holding trajectory r of energy k, and back.
/// Everything but `crossings` and `samples` (never checkpointed) is stored, and `chaotic`, the
/// ensemble's classification of r (ensemble_result::chaotic), for readers of older versions: it
/// is computed, not read back. The fields' one list (checkpoint.cpp, trajectory_fields) drives
/// both the writing and the parsing, as energy_fields does for energy records.
std::string trajectory_record(std::size_t energy, const trajectory_result& r, bool chaotic);
/// Parses a line written by trajectory_record (without the newline; the hash is checked).
/// Throws std::runtime_error describing the defect.
trajectory_result parse_trajectory_record(std::string_view line, std::size_t criteria,
                                          std::size_t& energy);

/// One line (with its hash and the newline) holding completed energy k: its timing, counts and
/// every criterion's statistics, exactly; and back. The label, energy and predictions are not
/// stored (the run's request and setup give them): parsing leaves them empty.
std::string energy_record(std::size_t energy, const energy_result& e);
/// Parses a line written by energy_record (without the newline; the hash is checked). Throws
/// std::runtime_error describing the defect.
energy_result parse_energy_record(std::string_view line, std::size_t criteria, std::size_t& energy);

/// Which records a checkpoint may hold: energy k's T records carry trajectory_criteria[k]
/// criteria; the E record of slot k * studies + p (study p at energy k) carries
/// energy_criteria[slot] criteria, 0 where study p has no energy k (such a record is refused).
struct checkpoint_layout {
    std::size_t studies = 1;
    std::vector<std::size_t> trajectory_criteria;  ///< per energy
    std::vector<std::size_t> energy_criteria;      ///< per slot (energies x studies)
    /// One study of `criteria` criteria at each of `energies` energies (slot = energy).
    static checkpoint_layout single(std::size_t energies, std::size_t criteria);
};

/// What a checkpoint holds.
struct checkpoint_content {
    bool exists = false;
    std::map<std::size_t, energy_result> completed;  ///< by slot (checkpoint_layout)
    /// energy -> (index -> result)
    std::map<std::size_t, std::map<std::uint64_t, trajectory_result>> trajectories;
    bool torn = false;  ///< the last line was incomplete or damaged and was dropped
};

/// Parses the text of a checkpoint against the header this run expects. Throws input_error
/// (naming --checkpoint, the file and, for another run's file, the first field that differs).
/// Energies with an E record have no T records left (the E records replace them).
checkpoint_content parse_checkpoint(const std::string& text, const nlohmann::ordered_json& header,
                                    const checkpoint_layout& layout,
                                    const std::filesystem::path& file);
/// One study: checkpoint_layout::single(header's energies, criteria).
checkpoint_content parse_checkpoint(const std::string& text, const nlohmann::ordered_json& header,
                                    std::size_t criteria, const std::filesystem::path& file);

/// Reads the file (absent: empty content, exists = false). Throws input_error when it exists
/// but cannot be read.
std::string read_checkpoint_text(const std::filesystem::path& file, bool& exists);

/// The writer (one per run; in MPI runs, rank 0's).
class checkpoint_writer {
  public:
    /// Starts the file: header plus the completed energies and trajectories of `content`,
    /// written atomically; appends go to it afterwards. `chaotic` classifies the trajectories of
    /// `content` for their records (trajectory_record); null: none is chaotic.
    checkpoint_writer(std::filesystem::path file, const nlohmann::ordered_json& header,
                      const checkpoint_content& content, double interval_seconds,
                      const std::function<bool(const trajectory_result&)>& chaotic = {});
    ~checkpoint_writer();
    checkpoint_writer(const checkpoint_writer&) = delete;
    checkpoint_writer& operator=(const checkpoint_writer&) = delete;

    /// Queues a T line (from trajectory_record); written when `interval` has passed.
    void add(std::string line);
    /// Writes the queued lines now.
    void flush();
    /// Energy k is complete: rewrites the file atomically as the header plus the E lines.
    void complete(std::size_t energy, const energy_result& done);
    /// An energy is complete for every study that has it: its E records (slot, statistics),
    /// written in one atomic rewrite.
    void complete(const std::vector<std::pair<std::size_t, const energy_result*>>& slots);
    std::uint64_t saved_trajectories() const { return saved_; }

  private:
    void rewrite(const std::string& tail);
    void open_for_append();
    std::filesystem::path file_;
    std::string header_line_, completed_lines_, pending_;
    double interval_;
    std::chrono::steady_clock::time_point last_flush_;
    int fd_ = -1;
    std::uint64_t saved_ = 0;
};

}  // namespace flipflux
