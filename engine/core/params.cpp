#include "params.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "error.h"

namespace foton {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace((unsigned char)s.front())) s.remove_prefix(1);
    while (!s.empty() && std::isspace((unsigned char)s.back())) s.remove_suffix(1);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    return s;
}

// Edit distance, for "did you mean".
std::size_t distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
            diag = up;
        }
    }
    return row[b.size()];
}

}  // namespace

IntegerText parse_integer(std::string_view text, uint64_t min, uint64_t max, uint64_t& out) {
    const std::string_view s = trim(text);
    if (s.empty()) return IntegerText::NotANumber;
    uint64_t u = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), u);
    if (ec == std::errc() && end == s.data() + s.size()) {
        out = u;
        return u < min || u > max ? IntegerText::OutOfRange : IntegerText::Ok;
    }
    if (ec == std::errc::result_out_of_range) return IntegerText::OutOfRange;
    double v = 0.0;
    auto [dend, dec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (dec != std::errc() || dend != s.data() + s.size()) return IntegerText::NotANumber;
    constexpr double kExact = 9007199254740992.0;  // 2^53
    if (!(v == std::floor(v)) || v < double(min) || v > double(max) || v > kExact || v < 0.0)
        return IntegerText::OutOfRange;
    out = uint64_t(v);
    return IntegerText::Ok;
}

namespace {
std::string range_text(uint64_t min, uint64_t max) {
    if (max != UINT64_MAX && max <= 1000000)
        return "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
    std::string r = min == 0   ? "a non-negative integer"
                    : min == 1 ? "a positive integer"
                               : "an integer of at least " + std::to_string(min);
    if (max != UINT64_MAX) r += " (at most " + std::to_string(max) + ")";
    return r;
}
}  // namespace

uint64_t integer_or_fail(std::string_view text, uint64_t min, uint64_t max, const std::string& file,
                         int line, const std::string& what) {
    uint64_t v = 0;
    switch (parse_integer(text, min, max, v)) {
        case IntegerText::Ok:
            return v;
        case IntegerText::NotANumber:
            throw InputError(file, line, what + " is not a number: '" + std::string(text) + "'");
        case IntegerText::OutOfRange:
            break;
    }
    throw InputError(file, line,
                     what + " must be " + range_text(min, max) + ", not " + std::string(text));
}

void ParamSet::set(const std::string& key, const std::string& value, const std::string& f,
                   int line) {
    for (Param& p : params_)
        if (p.key == key) {
            p = {key, value, f, line};
            return;
        }
    params_.push_back({key, value, f, line});
}

const ParamSet::Param* ParamSet::find(const std::string& key) const {
    if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) asked_.push_back(key);
    for (const Param& p : params_)
        if (p.key == key) {
            p.used = true;
            return &p;
        }
    return nullptr;
}

void ParamSet::fail(const Param& p, const std::string& what) const {
    throw InputError(p.file, p.line, what);
}

void ParamSet::fail(const std::string& key, const std::string& what) const {
    const Param* p = find(key);
    if (p) fail(*p, what);
    throw InputError(file, 0, what);
}

std::string ParamSet::text(const std::string& key, const std::string& fallback) const {
    const Param* p = find(key);
    return p ? p->value : fallback;
}

float ParamSet::real(const std::string& key, float fallback, float min, float max) const {
    const Param* p = find(key);
    if (!p) return fallback;
    const std::string_view s = trim(p->value);
    float v = 0.f;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
        fail(*p, "setting '" + key + "' is not a number: '" + p->value + "'");
    if (!std::isfinite(v)) fail(*p, "setting '" + key + "' is NaN or infinite");
    if (v < min || v > max) {
        std::string range = "setting '" + key + "' must be ";
        if (max >= 3.4e38f)
            range += min == 0.f ? "non-negative" : "at least " + std::to_string(min);
        else
            range += "in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
        fail(*p, range + ", not " + p->value);
    }
    return v;
}

float ParamSet::positive(const std::string& key, float fallback) const {
    const float v = real(key, fallback);
    if (!(v > 0.f)) fail(key, "setting '" + key + "' must be positive");
    return v;
}

uint64_t ParamSet::integer(const std::string& key, uint64_t fallback, uint64_t min,
                           uint64_t max) const {
    const Param* p = find(key);
    if (!p) return fallback;
    return integer_or_fail(p->value, min, max, p->file, p->line, "setting '" + key + "'");
}

bool ParamSet::boolean(const std::string& key, bool fallback) const {
    const Param* p = find(key);
    if (!p) return fallback;
    if (p->value == "true" || p->value == "1") return true;
    if (p->value == "false" || p->value == "0") return false;
    fail(*p, "setting '" + key + "' must be true or false, not '" + p->value + "'");
}

std::vector<std::string> ParamSet::read_keys() const {
    return asked_;
}

void ParamSet::warn(const std::string& key, const std::string& what) const {
    const Param* p = find(key);
    warnings_.push_back((p ? p->file + ":" + std::to_string(p->line) : file + ":0") + ": " + what);
}

void ParamSet::warn_unused(const std::vector<std::string>& keys, const std::string& what) const {
    for (const Param& p : params_)
        if (!p.used && std::find(keys.begin(), keys.end(), p.key) != keys.end()) {
            p.used = true;
            warnings_.push_back(p.file + ":" + std::to_string(p.line) + ": setting '" + p.key +
                                "' " + what);
        }
}

void ParamSet::reject_unused(const std::vector<std::string>& known) const {
    for (const Param& p : params_) {
        if (p.used) continue;
        std::string best;
        std::size_t best_d = 3;  // suggest only near misses
        for (const std::vector<std::string>* names :
             {&known, static_cast<const std::vector<std::string>*>(&asked_)})
            for (const std::string& k : *names) {
                const std::size_t d = distance(p.key, k);
                if (d < best_d) {
                    best_d = d;
                    best = k;
                }
            }
        fail(p, "unknown setting '" + p.key + "'" +
                    (best.empty() ? std::string() : " (did you mean '" + best + "'?)"));
    }
}

}  // namespace foton
