// foton serve's scene list (app/scene_list.h): subfolders and .pbrt files listed, names unique
// across roots with the same folder name, nothing reachable through a symlink out of a root.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "engine/app/scene_list.h"
#include "engine/core/error.h"
#include "test_util.h"

using namespace foton;
namespace fs = std::filesystem;

TEST_CASE("foton serve lists subfolders and .pbrt scenes, uniquely, and nothing outside",
          "[serve][fast]") {
    test::TempDir dir;
    const fs::path a = dir.path() / "a" / "scenes", b = dir.path() / "b" / "scenes";
    fs::create_directories(a / "sub");
    fs::create_directories(b);
    std::ofstream(a / "one.xml") << "<scene/>";
    std::ofstream(a / "sub" / "two.pbrt") << "WorldBegin";
    std::ofstream(a / "notes.txt") << "not a scene";
    std::ofstream(b / "one.xml") << "<scene/>";
    std::ofstream(dir.path() / "secret.xml") << "<scene/>";
    fs::create_symlink(dir.path() / "secret.xml", a / "escape.xml");
    const auto scenes = app::list_scenes({a.string(), b.string()});
    CHECK(scenes.count("a/scenes/one.xml") == 1);
    CHECK(scenes.count("a/scenes/sub/two.pbrt") == 1);
    CHECK(scenes.count("b/scenes/one.xml") == 1);
    CHECK(scenes.size() == 3);  // not notes.txt, not the symlink out of the root
    for (const auto& [name, path] : scenes) CHECK(name.find("escape") == std::string::npos);
    // One root keeps the short name.
    CHECK(app::list_scenes({b.string()}).count("scenes/one.xml") == 1);
    CHECK_THROWS_AS(app::list_scenes({(dir.path() / "none").string()}), InputError);
}
