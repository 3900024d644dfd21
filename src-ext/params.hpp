// Parameters of the LIGGGHTS decks, read from the decks themselves so that the decks stay the one
// place where defaults live (liggghts-inputs/common/grain-defaults.in, block-defaults.in and the
// impact parameters of liggghts-inputs/impact/setup.in).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/csv.hpp"         // shortest_number, the one text of a double
#include "common/provenance.hpp"  // fnv1a, the one hash of cache keys and deck digests

namespace ricochet::dem {
/// The seed of the dem layer's hashes (bed cache keys, replicate labels, deck digests), given to
/// fnv1a instead of FNV-1a's offset basis. It is that basis with a digit lost
/// (1469598103934665603, not 14695981039346656037), a slip found when the input provenance was
/// checked against the published FNV test vectors; it is kept so that the keys of existing bed
/// caches and campaign files and the digests of the shipped studies stay valid.
inline constexpr std::uint64_t kDemHashSeed = 1469598103934665603ull;
}  // namespace ricochet::dem

namespace ricochet::dem {

/// One `variable NAME index VALUE   # comment` line of a deck.
struct DeckParam {
  std::string name;
  std::string default_value;
  std::string comment;
  bool numeric = false;  ///< the default parses as a number
};

/// Reads the index variables of a deck file, in file order. Throws std::runtime_error naming the
/// file when it cannot be read.
std::vector<DeckParam> read_deck_params(const std::string& path);

/// Where the decks live and what they accept.
struct Decks {
  std::string root;                      ///< liggghts-inputs/
  std::string bed_deck;                  ///< root/bed/in.bed
  std::string impact_dir;                ///< root/impact (setup.in, check.in, finish.in)
  std::string common;                    ///< root/common
  std::vector<DeckParam> bed_params;     ///< grain-defaults.in: what makes a bed
  std::vector<DeckParam> block_params;   ///< block-defaults.in: grain-block contact
  std::vector<DeckParam> impact_params;  ///< setup.in: incident state and run control

  /// `root` = the liggghts-inputs folder; empty = liggghts_inputs_dir() (common/paths.hpp:
  /// $RICOCHET_LIGGGHTS_INPUTS, else share/ricochet/liggghts-inputs beside the program).
  /// Throws std::runtime_error when the decks are not there.
  static Decks locate(const std::string& root = "");
  /// Hash (16 hex digits, FNV-1a 64) of the text of every file a bed depends on (in.bed, bed/*.in
  /// and common/*.in) without comments and blank lines: part of the bed cache key, so editing a
  /// deck's commands invalidates cached beds and editing its comments does not.
  std::string bed_decks_digest() const;
};

/// Parameter overrides by section: "bed" (grain-defaults.in), "block" (block-defaults.in),
/// "run" (setup.in). Values are LIGGGHTS text (numbers in shortest round-trip form).
struct Overrides {
  std::map<std::string, std::string> bed, block, run;
};

/// Checks `name` = `value` against the section's parameters and the physical bounds documented in
/// docs/resolved-model.md (positive lengths, moduli and times; restitution in (0, 1]; friction
/// >= 0; seed a prime > 10000; mode slab|box; rolling_model epsd2|epsd|cdt). Throws
/// InputError(file, line, field = "section.name") listing the known names for an unknown one.
void check_param(const Decks& decks, const std::string& section, const std::string& name,
                 const std::string& value, const std::string& file, std::size_t line);
/// Applies "section.name=value" (as given to --set) to `o`, checked like check_param with
/// file "<command line>".
void apply_set_option(const Decks& decks, const std::string& assignment, Overrides& o);

/// A run.* parameter: its override in `run`, else the decks' default (impact/setup.in). Throws
/// std::logic_error for a name the deck does not have.
double run_param(const Decks& decks, const std::map<std::string, std::string>& run,
                 const std::string& name);
/// A bed parameter as the bed is built with it (effective_bed), as a number.
double bed_param(const Decks& decks, const std::map<std::string, std::string>& bed,
                 const std::string& name);
/// Steps between checkpoints, run_param's checkpoint_steps, or 0 (no checkpoints) for decks
/// without that parameter (pinned before 2026-12-05): impacts and bed builds (ensure_bed) both
/// use it.
long checkpoint_steps_of(const Decks& decks, const std::map<std::string, std::string>& run);

/// Effective bed parameters: the deck defaults overlaid with `bed` overrides, in deck order.
std::vector<std::pair<std::string, std::string>> effective_bed(
    const Decks& decks, const std::map<std::string, std::string>& bed);
/// Gravitational acceleration of every deck (`fix gravity ... 9.81` in impact/setup.in and
/// drop/setup.in): the dem layer's one copy, for the analyses of the decks' output [m/s^2].
inline constexpr double kDeckGravity_mps2 = 9.81;

/// Cache key of a bed: hash of the effective parameters and of the decks' text.
std::string bed_key(const Decks& decks, const std::map<std::string, std::string>& bed);

/// The k-th prime above 10000 (k >= 1): maps a replica seed 0, 1, 2... to LIGGGHTS seeds, which
/// must be primes above 10000.
std::int64_t liggghts_seed(std::int64_t replica, std::int64_t offset = 0);
/// `bed` with the bed seed of `replica` (liggghts_seed(replica)) unless `bed` sets `seed` itself
/// or there is no replica: the bed of an impact, a drop or `dem bed --seed`.
std::map<std::string, std::string> with_replica_seed(std::map<std::string, std::string> bed,
                                                     const std::optional<std::int64_t>& replica);
bool is_prime(std::int64_t n);

}  // namespace ricochet::dem
