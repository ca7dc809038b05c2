#include "aov.h"

#include <sstream>

namespace foton {

const EnumTable<uint32_t>& aov_names() {
    static const EnumTable<uint32_t> table{{{"albedo", kAovAlbedo},
                                            {"normal", kAovNormal},
                                            {"depth", kAovDepth},
                                            {"position", kAovPosition},
                                            {"variance", kAovVariance},
                                            {"samples", kAovSamples},
                                            {"components", kAovComponents},
                                            {"all", kAovAll}}};
    return table;
}

bool parse_aov_list(const std::string& text, uint32_t& bits, std::string& bad, uint32_t* named) {
    bits = 0;
    if (named) *named = 0;
    std::istringstream in(text);
    for (std::string name; std::getline(in, name, ',');) {
        // Spaces around a name are the list's, not the name's.
        const std::size_t b = name.find_first_not_of(" \t"), e = name.find_last_not_of(" \t");
        name = b == std::string::npos ? std::string() : name.substr(b, e - b + 1);
        uint32_t bit = 0;
        if (!aov_names().parse(name, bit)) {
            bad = name;
            return false;
        }
        bits |= bit;
        if (named && name != "all") *named |= bit;
    }
    return true;
}

std::string aov_list_text(uint32_t bits) {
    std::string s;
    for (const auto& [name, bit] : aov_names().entries)
        if (bit != kAovAll && (bits & bit)) {
            if (!s.empty()) s += ',';
            s += name;
        }
    return s;
}

std::vector<std::string> aov_channels(uint32_t bits) {
    static const std::pair<uint32_t, std::vector<std::string>> kChannels[] = {
        {kAovAlbedo, {"Albedo.R", "Albedo.G", "Albedo.B"}},
        {kAovNormal, {"N.X", "N.Y", "N.Z", "Ns.X", "Ns.Y", "Ns.Z"}},
        {kAovDepth, {"Z"}},
        {kAovPosition, {"P.X", "P.Y", "P.Z"}},
        {kAovVariance, {"Variance.R", "Variance.G", "Variance.B"}},
        {kAovSamples, {"samples"}},
    };
    std::vector<std::string> out;
    for (const auto& [bit, names] : kChannels)
        if (bits & bit) out.insert(out.end(), names.begin(), names.end());
    return out;
}

AovLayer samples_layer(const std::vector<uint32_t>& samples_per_pixel) {
    AovLayer l{"samples", aov_channels(kAovSamples), {}};
    l.values.assign(samples_per_pixel.begin(), samples_per_pixel.end());
    return l;
}

const AovLayer* find_aov(const std::vector<AovLayer>& layers, const std::string& name) {
    for (const AovLayer& l : layers)
        if (l.name == name) return &l;
    return nullptr;
}

}  // namespace foton
