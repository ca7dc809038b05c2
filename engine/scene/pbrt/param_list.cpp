#include "param_list.h"

#include <cmath>

#include "engine/core/error.h"
#include "spectrum.h"

namespace foton::pbrt {

namespace {

bool is_triple_type(const std::string& t) {
    return t == "point3" || t == "vector3" || t == "normal3" || t == "normal" || t == "point" ||
           t == "vector";
}

}  // namespace

const Param* ParamList::find(const std::string& name) const {
    const Param* found = nullptr;
    for (const Param& p : params)
        if (p.name == name) found = &p;  // a repeated parameter: the last one counts
    if (found) found->used = true;
    return found;
}

void ParamList::fail(const Param& p, const std::string& what) const {
    throw InputError(p.file, p.line, "parameter '" + p.type + " " + p.name + "': " + what);
}

namespace {

const Param* typed(const ParamList& l, const std::string& name,
                   std::initializer_list<const char*> types) {
    const Param* p = l.find(name);
    if (!p) return nullptr;
    for (const char* t : types)
        if (p->type == t) return p;
    std::string want;
    for (const char* t : types) want += (want.empty() ? "" : " or ") + std::string(t);
    l.fail(*p, "expected type " + want);
}

}  // namespace

float ParamList::real(const std::string& name, float fallback) const {
    const Param* p = typed(*this, name, {"float"});
    if (!p) return fallback;
    if (p->numbers.size() != 1) fail(*p, "expected one value");
    return float(p->numbers[0]);
}

int ParamList::integer(const std::string& name, int fallback) const {
    const Param* p = typed(*this, name, {"integer"});
    if (!p) return fallback;
    if (p->numbers.size() != 1) fail(*p, "expected one value");
    return int(p->numbers[0]);
}

bool ParamList::boolean(const std::string& name, bool fallback) const {
    const Param* p = typed(*this, name, {"bool"});
    if (!p) return fallback;
    if (p->strings.size() != 1) fail(*p, "expected one value, true or false");
    return p->strings[0] == "true";
}

std::string ParamList::text(const std::string& name, const std::string& fallback) const {
    const Param* p = typed(*this, name, {"string"});
    if (!p) return fallback;
    if (p->strings.size() != 1) fail(*p, "expected one string");
    return p->strings[0];
}

std::vector<float> ParamList::reals(const std::string& name) const {
    const Param* p = typed(*this, name, {"float"});
    if (!p) return {};
    return {p->numbers.begin(), p->numbers.end()};
}

std::vector<int> ParamList::integers(const std::string& name) const {
    const Param* p = typed(*this, name, {"integer"});
    if (!p) return {};
    std::vector<int> v;
    v.reserve(p->numbers.size());
    for (double d : p->numbers) v.push_back(int(d));
    return v;
}

std::vector<Vec3> ParamList::triples(const std::string& name) const {
    const Param* p = find(name);
    if (!p) return {};
    if (!is_triple_type(p->type)) fail(*p, "expected point3, vector3 or normal3 values");
    if (p->numbers.size() % 3 != 0) fail(*p, "the number of values is not a multiple of 3");
    std::vector<Vec3> v(p->numbers.size() / 3);
    for (std::size_t i = 0; i < v.size(); ++i)
        v[i] = {float(p->numbers[3 * i]), float(p->numbers[3 * i + 1]),
                float(p->numbers[3 * i + 2])};
    return v;
}

std::vector<float> ParamList::pairs(const std::string& name) const {
    const Param* p = typed(*this, name, {"point2", "vector2", "float"});
    if (!p) return {};
    if (p->numbers.size() % 2 != 0) fail(*p, "the number of values is not a multiple of 2");
    return {p->numbers.begin(), p->numbers.end()};
}

std::vector<RGB> ParamList::colors(const std::string& name) const {
    const Param* p = find(name);
    if (!p) return {};
    if (p->type != "rgb" && p->type != "color") fail(*p, "expected rgb values");
    if (p->numbers.size() % 3 != 0) fail(*p, "the number of values is not a multiple of 3");
    std::vector<RGB> v(p->numbers.size() / 3);
    for (std::size_t i = 0; i < v.size(); ++i) {
        v[i] = {float(p->numbers[3 * i]), float(p->numbers[3 * i + 1]),
                float(p->numbers[3 * i + 2])};
        if (!(v[i].r >= 0.f && v[i].g >= 0.f && v[i].b >= 0.f))
            fail(*p, "colour components must not be negative");
    }
    return v;
}

std::optional<RGB> ParamList::color(const std::string& name, bool illuminant) const {
    const Param* p = find(name);
    if (!p) return std::nullopt;
    if (p->type == "rgb" || p->type == "color") {
        if (p->numbers.size() != 3) fail(*p, "expected three values");
        const RGB c{float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2])};
        if (c.r < 0.f || c.g < 0.f || c.b < 0.f) fail(*p, "colour components must not be negative");
        return c;
    }
    if (p->type == "blackbody") {
        if (p->numbers.size() != 1 || !(p->numbers[0] > 0.0))
            fail(*p, "expected one positive temperature in kelvin");
        return blackbody_rgb(float(p->numbers[0]));
    }
    if (p->type == "spectrum") {
        if (p->strings.size() == 1 && p->numbers.empty()) {
            const auto c = named_spectrum_rgb(p->strings[0]);
            if (!c)
                fail(*p, "unknown named spectrum '" + p->strings[0] + "' (" +
                             named_spectrum_list() + "), and no spectrum file of that name");
            return c;
        }
        if (p->numbers.size() < 2 || p->numbers.size() % 2 != 0)
            fail(*p, "expected (wavelength, value) pairs");
        std::vector<float> v(p->numbers.begin(), p->numbers.end());
        for (std::size_t i = 2; i < v.size(); i += 2)
            if (!(v[i] > v[i - 2])) fail(*p, "wavelengths must increase");
        for (std::size_t i = 1; i < v.size(); i += 2)
            if (v[i] < 0.f) fail(*p, "spectrum values must not be negative");
        return sampled_spectrum_rgb(v, illuminant);
    }
    if (p->type == "float") {
        if (p->numbers.size() != 1) fail(*p, "expected one value");
        return RGB{float(p->numbers[0])};
    }
    fail(*p, "expected an rgb, spectrum or blackbody value");
}

std::string ParamList::texture(const std::string& name) const {
    for (const Param& p : params)
        if (p.name == name && p.type == "texture") {
            p.used = true;
            if (p.strings.size() != 1) fail(p, "expected one texture name");
            return p.strings[0];
        }
    return "";
}

std::vector<std::string> ParamList::unused(const std::string& what) const {
    std::vector<std::string> out;
    for (const Param& p : params)
        if (!p.used)
            out.push_back(p.file + ":" + std::to_string(p.line) + ": unsupported parameter '" +
                          p.type + " " + p.name + "' of " + what + " (ignored)");
    return out;
}

}  // namespace foton::pbrt
