#include "input_file.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "error.h"

namespace foton {

namespace {
std::vector<std::string>& confinement() {
    static std::vector<std::string> folders;
    return folders;
}

// Whether `path`, symlinks resolved, lies in one of the confinement folders.
bool confined(const std::string& path) {
    namespace fs = std::filesystem;
    if (confinement().empty()) return true;
    std::error_code ec;
    const std::string real = fs::weakly_canonical(path, ec).string();
    if (ec) return false;
    for (const std::string& f : confinement())
        if (real.compare(0, f.size(), f) == 0 &&
            (real.size() == f.size() || real[f.size()] == '/' || f == "/"))
            return true;
    return false;
}
}  // namespace

void confine_inputs(const std::vector<std::string>& folders) {
    namespace fs = std::filesystem;
    confinement().clear();
    for (const std::string& f : folders) {
        std::error_code ec;
        const fs::path real = fs::weakly_canonical(f, ec);
        confinement().push_back(ec ? f : real.string());
    }
}

const std::vector<std::string>& input_confinement() {
    return confinement();
}

std::string input_file_problem(const std::string& path, uint64_t max_bytes) {
    namespace fs = std::filesystem;
    if (!confined(path)) {
        std::string list;
        for (const std::string& f : confinement()) list += (list.empty() ? "" : ", ") + f;
        return "outside the folders this server reads (" + list + "; see --allow-read)";
    }
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (st.type() == fs::file_type::not_found || ec == std::errc::no_such_file_or_directory)
        return "not found";
    if (ec) return ec.message();
    if (st.type() == fs::file_type::directory) return "it is a directory";
    if (st.type() != fs::file_type::regular) return "not a regular file (a pipe or a device?)";
    const uint64_t size = fs::file_size(path, ec);
    if (ec) return ec.message();
    if (size > max_bytes)
        return "it is " + std::to_string(size >> 20) + " MiB, more than the " +
               std::to_string(max_bytes >> 20) + " MiB allowed";
    return "";
}

std::string read_input_file(const std::string& path, uint64_t max_bytes, const char* what) {
    const std::string problem = input_file_problem(path, max_bytes);
    if (!problem.empty())
        throw InputError(path, 0, std::string("cannot read ") + what + ": " + problem);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, 0, std::string("cannot open ") + what);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw InputError(path, 0, std::string("error reading ") + what);
    return text;
}

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower((unsigned char)c));
    return ext;
}

}  // namespace foton
