// Reading the tokens of a directive: its string and number arguments and its parameter
// list, each value checked for type and range at its line.
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "engine/core/error.h"
#include "engine/core/input_file.h"
#include "importer.h"
#include "spectrum.h"

namespace foton::pbrt {

Token Importer::expect_string(const Token& directive, const char* what) {
    const Token& p = files_.back()->peek();
    if (p.kind != TokenKind::String)
        fail(directive, std::string(directive.text) + " needs " + what + " (a quoted string)");
    return files_.back()->next();
}

float Importer::expect_number(const Token& directive) {
    const Token t = files_.back()->next();
    double v = 0.0;
    if (t.kind == TokenKind::Number) {
        auto [ptr, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), v);
        if (ec == std::errc() && ptr == t.text.data() + t.text.size() && std::isfinite(v)) {
            if (std::fabs(v) > double(std::numeric_limits<float>::max()))
                fail(t, std::string(directive.text) + ": '" + std::string(t.text) +
                            "' is beyond the range of a float");
            return float(v);
        }
    }
    fail(t.kind == TokenKind::End ? directive : t,
         std::string(directive.text) + " expects a number, got '" + std::string(t.text) + "'");
}

namespace {

bool numeric_type(const std::string& t) {
    return t == "integer" || t == "float" || t == "point2" || t == "vector2" || t == "point3" ||
           t == "vector3" || t == "normal3" || t == "normal" || t == "point" || t == "vector" ||
           t == "rgb" || t == "color" || t == "blackbody";
}

bool known_type(const std::string& t) {
    return numeric_type(t) || t == "spectrum" || t == "bool" || t == "string" || t == "texture";
}

}  // namespace

std::vector<double> Importer::spectrum_file_pairs(const Token& t, const std::string& rel) {
    const std::string path = input_path(t, "spectrum file", rel, kMaxSpectrumFileBytes);
    std::ifstream in(path);
    std::vector<double> v;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        line = line.substr(0, line.find('#'));
        std::istringstream words(line);
        std::string w;
        while (words >> w) {
            double x = 0.0;
            auto [ptr, ec] = std::from_chars(w.data(), w.data() + w.size(), x);
            if (ec != std::errc() || ptr != w.data() + w.size() || !std::isfinite(x))
                throw InputError(path, n,
                                 "'" + w +
                                     "' is not a number (a spectrum file holds "
                                     "wavelength-value pairs)");
            v.push_back(x);
        }
    }
    if (v.size() < 2 || v.size() % 2 != 0)
        throw InputError(path, 0,
                         "a spectrum file holds wavelength-value pairs, and this has " +
                             std::to_string(v.size()) + " numbers");
    return v;
}

ParamList Importer::read_params() {
    ParamList list;
    list.file = file();
    Tokenizer& tk = *files_.back();
    while (tk.peek().kind == TokenKind::String) {
        const Token decl = tk.next();
        Param p;
        p.file = file();
        p.line = decl.line;
        const std::string d(decl.text);
        std::size_t a = d.find_first_not_of(" \t"), b = d.find_first_of(" \t", a);
        const std::size_t c = d.find_first_not_of(" \t", b), e = d.find_last_not_of(" \t");
        if (a == std::string::npos || b == std::string::npos || c == std::string::npos ||
            d.find_first_of(" \t", c) < e)
            fail(decl, "malformed parameter '" + d + "' (expected \"type name\")");
        p.type = d.substr(a, b - a);
        p.name = d.substr(c, e + 1 - c);
        if (!known_type(p.type)) fail(decl, "unknown parameter type '" + p.type + "'");
        auto value = [&](const Token& v) {
            if (v.kind == TokenKind::Number) {
                double x = 0.0;
                auto [ptr, ec] = std::from_chars(v.text.data(), v.text.data() + v.text.size(), x);
                if (ec != std::errc() || ptr != v.text.data() + v.text.size() || !std::isfinite(x))
                    fail(v, "parameter '" + p.name + "': '" + std::string(v.text) +
                                "' is not a finite number");
                if (p.type != "integer" && std::fabs(x) > double(std::numeric_limits<float>::max()))
                    fail(v, "parameter '" + p.name + "': '" + std::string(v.text) +
                                "' is beyond the range of a float");
                if (p.type == "integer" && (x != std::floor(x) || std::fabs(x) > 2147483647.0))
                    fail(v, "parameter '" + p.name + "': '" + std::string(v.text) +
                                "' is not an integer");
                p.numbers.push_back(x);
            } else if (v.kind == TokenKind::String || v.kind == TokenKind::Word) {
                if (v.kind == TokenKind::Word && v.text != "true" && v.text != "false")
                    fail(v, "parameter '" + p.name + "': '" + std::string(v.text) + "' is not " +
                                (numeric_type(p.type) ? "a number" : "a value"));
                p.strings.emplace_back(v.text);
            } else {
                fail(v, "parameter '" + p.name + "' has no value");
            }
        };
        if (tk.peek().kind == TokenKind::Open) {
            tk.next();
            for (;;) {
                const Token v = tk.next();
                if (v.kind == TokenKind::Close) break;
                if (v.kind == TokenKind::End || v.kind == TokenKind::Open)
                    fail(decl, "parameter '" + p.name + "': missing ']'");
                value(v);
            }
        } else {
            value(tk.next());
        }
        const bool numeric = numeric_type(p.type);
        if (numeric && !p.strings.empty())
            fail(decl, "parameter '" + p.type + " " + p.name + "' takes numbers");
        if ((p.type == "string" || p.type == "texture" || p.type == "bool") && !p.numbers.empty())
            fail(decl, "parameter '" + p.type + " " + p.name + "' takes quoted strings");
        if (p.type == "bool")
            for (const std::string& s : p.strings)
                if (s != "true" && s != "false")
                    fail(decl, "parameter '" + p.name + "' must be true or false");
        if (p.numbers.empty() && p.strings.empty())
            fail(decl, "parameter '" + p.type + " " + p.name + "' has no values");
        // A spectrum named by a file (pbrt-v4's .spd: wavelength-value pairs) becomes its pairs;
        // a name that is neither a spectrum's nor a file's is reported where it is read.
        if (p.type == "spectrum" && p.strings.size() == 1 && p.numbers.empty() &&
            !named_spectrum_rgb(p.strings[0]) &&
            input_file_problem((std::filesystem::path(base_) / p.strings[0]).string(),
                               kMaxSpectrumFileBytes) != "not found") {
            p.numbers = spectrum_file_pairs(decl, p.strings[0]);
            p.strings.clear();
        }
        list.params.push_back(std::move(p));
    }
    return list;
}

}  // namespace foton::pbrt
