#pragma once
// Who may drive `foton serve`. The server listens on the loopback interface, but any page the
// user's browser opens can send requests there: a form POST from another site is a "simple"
// cross-origin request that needs no preflight, and a DNS-rebinding site reaches 127.0.0.1 under
// its own host name. So:
//   * when bound to loopback, the Host header must name this server (127.0.0.1, localhost or
//     [::1] with its port): a rebinding host name is refused;
//   * a request that changes state (any method but GET and HEAD) must carry the page's
//     `X-Foton-Request: 1` header, which a foreign page cannot add without a CORS preflight
//     that this server never grants, and its Origin (if sent) must be this server's;
//   * browsers' Sec-Fetch-Site must not say cross-site for the API.
// The server sends no CORS headers, so foreign pages cannot read its answers either.
#include <string>

namespace foton::app {

inline constexpr const char* kRequestTokenHeader = "X-Foton-Request";

struct RequestView {
    std::string method, path;
    std::string host;            // the Host header
    std::string origin;          // Origin, "" when absent
    std::string sec_fetch_site;  // Sec-Fetch-Site, "" when absent
    std::string token;           // X-Foton-Request, "" when absent
};

// Whether `host` (a --host value) is this machine's loopback interface.
bool is_loopback_host(const std::string& host);

// "" when the request may be served; otherwise why not (for a 403 answer).
std::string refuse_reason(const RequestView& request, const std::string& bound_host, int port);

}  // namespace foton::app
