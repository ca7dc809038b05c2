#include "request_guard.h"

namespace foton::app {

namespace {

bool starts_with(const std::string& s, const char* prefix) {
    return s.rfind(prefix, 0) == 0;
}

}  // namespace

bool is_loopback_host(const std::string& host) {
    return host == "127.0.0.1" || host == "localhost" || host == "::1" || host == "[::1]";
}

std::string refuse_reason(const RequestView& r, const std::string& bound_host, int port) {
    if (is_loopback_host(bound_host)) {
        // "name:port" with a loopback name and this server's port.
        const std::size_t colon = r.host.rfind(':');
        const bool ours = colon != std::string::npos &&
                          r.host.compare(colon + 1, std::string::npos, std::to_string(port)) == 0 &&
                          is_loopback_host(r.host.substr(0, colon)) &&
                          r.host.compare(0, colon, "::1") != 0;  // IPv6 needs its brackets
        if (!ours) return std::string("Host '") + r.host + "' is not this server";
    }
    const bool changes_state = r.method != "GET" && r.method != "HEAD";
    const bool api = starts_with(r.path, "/api/");
    if (!r.sec_fetch_site.empty() && r.sec_fetch_site != "same-origin" &&
        r.sec_fetch_site != "none" && (changes_state || api))
        return std::string("a ") + r.sec_fetch_site + " request (Sec-Fetch-Site)";
    if (!changes_state) return {};
    if (r.token != "1")
        return std::string("a request that changes state needs the page's ") + kRequestTokenHeader +
               " header";
    if (!r.origin.empty() && r.origin != std::string("http://") + r.host)
        return std::string("a request from origin '") + r.origin + "'";
    return {};
}

}  // namespace foton::app
