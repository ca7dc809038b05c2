#pragma once
// Typed settings from text: a ParamSet holds key=value pairs as written (in a scene file's
// <renderer>, or on the command line's --set) with where each came from, and hands them out
// as checked numbers, booleans and enum values. Every problem is an InputError naming the
// file and line of the offending setting; a key nobody asked for is an error too
// (reject_unused), with the closest known key suggested, so a misspelt setting never passes
// silently.
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace foton {

// The names of an enum's values: one table per enum serves parsing, printing and the list
// in error messages. Aliases follow the first name of a value.
template <class E>
struct EnumTable {
    std::vector<std::pair<const char*, E>> entries;
    bool parse(std::string_view s, E& out) const {
        for (const auto& [name, value] : entries)
            if (s == name) {
                out = value;
                return true;
            }
        return false;
    }
    const char* name(E e) const {
        for (const auto& [n, value] : entries)
            if (value == e) return n;
        return "?";
    }
    // "a, b, c": the first name of each value.
    std::string list() const {
        std::string s;
        for (std::size_t i = 0; i < entries.size(); ++i) {
            bool alias = false;
            for (std::size_t j = 0; j < i; ++j) alias |= entries[j].second == entries[i].second;
            if (alias) continue;
            if (!s.empty()) s += ", ";
            s += entries[i].first;
        }
        return s;
    }
};

// An integer in [min, max] from text: digits are read exactly (any size up to 2^64 - 1);
// float notation (1e6) is accepted when its value is an integer up to 2^53, where doubles
// are exact. One parser for the scene file, --set and the command line's numbers.
enum class IntegerText { Ok, NotANumber, OutOfRange };
IntegerText parse_integer(std::string_view text, uint64_t min, uint64_t max, uint64_t& out);
// The same, or an InputError at `file` naming `what` ("--seed", "attribute 'width'").
uint64_t integer_or_fail(std::string_view text, uint64_t min, uint64_t max, const std::string& file,
                         int line, const std::string& what);

class ParamSet {
  public:
    // Sets `key` (a later set of the same key replaces it: --set after the file).
    void set(const std::string& key, const std::string& value, const std::string& file, int line);
    bool has(const std::string& key) const { return find(key) != nullptr; }
    // The text of `key`, or `fallback`.
    std::string text(const std::string& key, const std::string& fallback = "") const;
    // An integer in [min, max].
    uint64_t integer(const std::string& key, uint64_t fallback, uint64_t min = 0,
                     uint64_t max = UINT64_MAX) const;
    // A finite number in [min, max].
    float real(const std::string& key, float fallback, float min = -3.4e38f,
               float max = 3.4e38f) const;
    // A positive finite number.
    float positive(const std::string& key, float fallback) const;
    bool boolean(const std::string& key, bool fallback) const;
    template <class E>
    E choice(const std::string& key, const EnumTable<E>& table, E fallback,
             const char* what = nullptr) const {
        const Param* p = find(key);
        if (!p) return fallback;
        E e;
        if (!table.parse(p->value, e))
            fail(*p, std::string("unknown ") + (what ? what : key.c_str()) + " '" + p->value +
                         "' (" + table.list() + ")");
        return e;
    }
    // An error about `key`'s value, at its file and line (or `file`:0 when it is not set).
    [[noreturn]] void fail(const std::string& key, const std::string& what) const;
    // A warning about `key` at its file and line ("file:line: what"), kept in warnings(): for
    // a setting that applies to another integrator than the one running, which is ignored.
    void warn(const std::string& key, const std::string& what) const;
    const std::vector<std::string>& warnings() const { return warnings_; }
    // Unused keys among `keys` (which another reader knows) are warned about with `what`
    // after the key's name, and count as read.
    void warn_unused(const std::vector<std::string>& keys, const std::string& what) const;
    // Throws for the first key that no getter has read, suggesting the closest of `known`
    // (or of the keys read) when one is near.
    void reject_unused(const std::vector<std::string>& known = {}) const;
    // Every key read so far.
    std::vector<std::string> read_keys() const;
    // The set's own file (for errors about missing keys).
    std::string file;

  private:
    struct Param {
        std::string key, value, file;
        int line = 0;
        mutable bool used = false;
    };
    const Param* find(const std::string& key) const;
    [[noreturn]] void fail(const Param& p, const std::string& what) const;
    std::vector<Param> params_;
    mutable std::vector<std::string> asked_;
    mutable std::vector<std::string> warnings_;
};

}  // namespace foton
