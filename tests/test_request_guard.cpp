// foton serve's request guard (app/request_guard.h): what a foreign page or a DNS-rebinding
// host name can send is refused; what the server's own page sends passes.
#include <catch2/catch.hpp>

#include "engine/app/request_guard.h"

using namespace foton::app;

TEST_CASE("foton serve refuses cross-site and rebinding requests, serves its own page",
          "[serve][fast]") {
    const std::string host = "127.0.0.1";
    const int port = 8080;
    RequestView page{
        "POST", "/api/render", "127.0.0.1:8080", "http://127.0.0.1:8080", "same-origin", "1"};
    CHECK(refuse_reason(page, host, port).empty());
    RequestView get{"GET", "/api/status", "localhost:8080", "", "", ""};
    CHECK(refuse_reason(get, host, port).empty());
    get.host = "[::1]:8080";
    CHECK(refuse_reason(get, host, port).empty());

    // A form posted by another site: no token, a foreign origin, cross-site.
    RequestView form{"POST", "/api/render", "127.0.0.1:8080", "https://evil.example", "cross-site",
                     ""};
    CHECK_THAT(refuse_reason(form, host, port), Catch::Contains("cross-site"));
    form.sec_fetch_site.clear();  // an older browser
    CHECK_THAT(refuse_reason(form, host, port), Catch::Contains("X-Foton-Request"));
    form.token.push_back('1');  // a browser would not send it without a preflight we never grant
    CHECK_THAT(refuse_reason(form, host, port), Catch::Contains("evil.example"));
    // The page's stop button without the token (e.g. a link from elsewhere).
    CHECK(!refuse_reason({"POST", "/api/stop", "127.0.0.1:8080", "", "", ""}, host, port).empty());
    // DNS rebinding: this server reached under another host name, or another port.
    CHECK_THAT(
        refuse_reason({"GET", "/api/image.exr", "evil.example:8080", "", "", ""}, host, port),
        Catch::Contains("evil.example"));
    CHECK(!refuse_reason({"GET", "/", "127.0.0.1:9999", "", "", ""}, host, port).empty());
    CHECK(!refuse_reason({"GET", "/", "", "", "", ""}, host, port).empty());
    // A cross-site read of the API (an <img> of the preview on a foreign page).
    CHECK(!refuse_reason({"GET", "/api/image.png", "127.0.0.1:8080", "", "cross-site", ""}, host,
                         port)
               .empty());
    // Bound to every interface (--host 0.0.0.0) the Host check is off; the rest stays.
    CHECK(refuse_reason({"GET", "/", "192.168.1.5:8080", "", "", ""}, "0.0.0.0", port).empty());
    CHECK(!refuse_reason({"POST", "/api/render", "192.168.1.5:8080", "", "", ""}, "0.0.0.0", port)
               .empty());
}
