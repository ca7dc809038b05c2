// VDB volume files: OpenVDB and NanoVDB grids read as density grids equal OpenVDB's own
// trilinear sampling everywhere (inside, at the padded faces, outside), placed by the file's
// transform and the scene's; the XML and pbrt-v4 forms and every refusal.
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/ValueTransformer.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <string>

#include "engine/core/error.h"
#include "engine/core/rng.h"
#include "engine/film/metrics.h"
#include "engine/scene/pbrt/spectrum.h"
#include "engine/scene/pbrt_loader.h"
#include "engine/scene/vdb_file.h"
#include "engine/scene/xml_loader.h"
#include "test_util.h"

using namespace foton;

namespace {

// An uneven cloud of active voxels about index (3, -2, 5), voxel size 0.25, offset (1, 0, -2).
openvdb::FloatGrid::Ptr test_cloud() {
    openvdb::initialize();
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.f);
    g->setName("density");
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(0.25);
    xf->postTranslate(openvdb::Vec3d(1.0, 0.0, -2.0));
    g->setTransform(xf);
    auto acc = g->getAccessor();
    for (int k = -3; k <= 13; ++k)
        for (int j = -10; j <= 6; ++j)
            for (int i = -5; i <= 11; ++i) {
                const float r2 = float((i - 3) * (i - 3) + (j + 2) * (j + 2) + (k - 5) * (k - 5));
                const float v = std::max(0.f, 1.f - r2 / 64.f) * (1.2f + std::sin(0.9f * i * j));
                if (v > 0.f) acc.setValue(openvdb::Coord(i, j, k), v);
            }
    return g;
}

void write_vdb(const std::string& path, const openvdb::GridPtrVec& grids) {
    openvdb::io::File f(path);
    f.write(grids);
    f.close();
}

// The XML scene around one vdb medium.
std::string xml_with(const std::string& medium) {
    return "<scene><film width=\"8\" height=\"8\"/>\n<media>" + medium +
           "</media>\n<objects><sphere radius=\"9\" medium_inside=\"m\"><center x=\"0\" y=\"0\" "
           "z=\"0\"/><material type=\"interface\"/></sphere></objects>\n<renderer "
           "type=\"volpath\"/><camera><eye x=\"0\" y=\"0\" z=\"30\"/><target x=\"0\" y=\"0\" "
           "z=\"0\"/></camera></scene>";
}

}  // namespace

TEST_CASE("vdb: OpenVDB and NanoVDB files read as grids equal to OpenVDB's trilinear sampling",
          "[media][fast]") {
    test::TempDir dir;
    const openvdb::FloatGrid::Ptr cloud = test_cloud();
    write_vdb(dir.file("cloud.vdb"), {cloud});
    nanovdb::io::writeGrid(dir.file("cloud.nvdb"), nanovdb::openToNanoVDB(*cloud));
    // Placed by a scale of 2 and a translation after the file's own map.
    const std::string placement =
        "<transform><scale x=\"2\" y=\"2\" z=\"2\"/><translate x=\"0.5\" y=\"-1\" "
        "z=\"0\"/></transform>";
    const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(
        *cloud);
    for (const char* file : {"cloud.vdb", "cloud.nvdb"}) {
        INFO(file);
        const Scene s =
            parse_scene(xml_with(std::string("<medium name=\"m\" type=\"vdb\" src=\"") + file +
                                 "\"><sigma_s r=\"1\" g=\"1\" b=\"1\"/>" + placement + "</medium>"),
                        "v.xml", dir.path().string());
        REQUIRE(s.media.size() == 1);
        const DensityGrid& d = *s.media[0].density;
        // Active voxels -4..10 in x (|i - 3| < 8), padded by one on each side.
        CHECK(d.nx() == 15 + 2);
        // The box: index -5.5 .. 11.5 in x, world 0.25 i + 1, then 2 w + 0.5.
        CHECK(d.box().lo.x == Approx(2.f * (0.25f * -5.5f + 1.f) + 0.5f));
        CHECK(d.box().hi.x == Approx(2.f * (0.25f * 11.5f + 1.f) + 0.5f));
        int inside = 0;
        double worst = 0.0;
        for (uint64_t n = 0; n < 20000; ++n) {
            // Points over a region larger than the box, so faces and outside are covered.
            const Vec3 w{-6.f + 14.f * rng::uniform(5, 1, n, 0),
                         -12.f + 16.f * rng::uniform(5, 1, n, 1),
                         -12.f + 18.f * rng::uniform(5, 1, n, 2)};
            const Vec3 f{(w.x - 0.5f) / 2.f, (w.y + 1.f) / 2.f, w.z / 2.f};  // the file's world
            const float expected = sampler.wsSample(openvdb::Vec3R(f.x, f.y, f.z));
            if (expected > 0.f) ++inside;
            worst = std::max(worst, double(std::fabs(d.lookup(w) - expected)));
        }
        CHECK(inside > 1000);
        CHECK(worst < 2e-5);
    }
}

TEST_CASE("vdb: bad files and grids are refused with the file, line and reason", "[media][fast]") {
    test::TempDir dir;
    const openvdb::FloatGrid::Ptr cloud = test_cloud();
    // A level set, a vector grid, a rotated grid and one with a background of 1 beside it.
    openvdb::FloatGrid::Ptr level = openvdb::FloatGrid::create(3.f);
    level->setName("surface");
    level->setGridClass(openvdb::GRID_LEVEL_SET);
    level->getAccessor().setValue(openvdb::Coord(0, 0, 0), -1.f);
    openvdb::Vec3SGrid::Ptr velocity = openvdb::Vec3SGrid::create();
    velocity->setName("v");
    velocity->getAccessor().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
    openvdb::FloatGrid::Ptr turned = cloud->deepCopy();
    turned->setName("turned");
    turned->transform().postRotate(0.3, openvdb::math::Y_AXIS);
    openvdb::FloatGrid::Ptr haze = openvdb::FloatGrid::create(1.f);
    haze->setName("haze");
    haze->getAccessor().setValue(openvdb::Coord(0, 0, 0), 2.f);
    write_vdb(dir.file("all.vdb"), {cloud, level, velocity, turned, haze});
    {
        std::ofstream f(dir.file("junk.vdb"), std::ios::binary);
        f << "not a volume at all";
    }
    // A NanoVDB file cut short: the reader must not trust what is missing.
    nanovdb::io::writeGrid(dir.file("cloud.nvdb"), nanovdb::openToNanoVDB(*cloud));
    {
        std::ifstream in(dir.file("cloud.nvdb"), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream out(dir.file("cut.nvdb"), std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size() / 2));
    }
    auto error_of = [&](const std::string& attrs) -> std::string {
        try {
            parse_scene(xml_with("<medium name=\"m\" type=\"vdb\" " + attrs +
                                 "><sigma_s r=\"1\" g=\"1\" b=\"1\"/></medium>"),
                        "v.xml", dir.path().string());
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    auto says = [](const std::string& message, const std::string& part) {
        const bool found = message.find(part) != std::string::npos;
        if (!found) UNSCOPED_INFO("the message: " << message);
        return found;
    };
    CHECK(error_of("src=\"all.vdb\"").empty());
    CHECK(says(error_of("src=\"all.vdb\" grid=\"smoke\""),
               "v.xml:2: volume file 'all.vdb': has no grid named 'smoke' (its grids: density, "
               "haze, surface, turned, v)"));
    CHECK(says(error_of("src=\"all.vdb\" grid=\"surface\""), "is a level set, not a fog volume"));
    CHECK(says(error_of("src=\"all.vdb\" grid=\"v\""), "holds vec3s, not float"));
    CHECK(says(error_of("src=\"all.vdb\" grid=\"turned\""), "rotates or shears it"));
    CHECK(says(error_of("src=\"all.vdb\" grid=\"haze\""), "the grid's background is 1"));
    CHECK(says(error_of("src=\"junk.vdb\""), "is neither an OpenVDB nor a NanoVDB file"));
    CHECK(says(error_of("src=\"cut.nvdb\""), "v.xml:2: volume file 'cut.nvdb': "));
    CHECK(says(error_of("src=\"none.vdb\""), "volume file 'none.vdb': not found"));
    CHECK(says(error_of("src=\"all.vdb\" nx=\"3\""), "'nx' belongs to a grid medium"));
    CHECK(says(error_of("src=\"\""), "a vdb medium needs 'src'"));
    CHECK_THROWS_AS(read_vdb_density(dir.file("cloud.nvdb"), "density", Affine{}, 1000), VdbError);
}

TEST_CASE("vdb: pbrt-v4's nanovdb medium, placed by the transform, its temperature glowing",
          "[media][fast]") {
    test::TempDir dir;
    const openvdb::FloatGrid::Ptr cloud = test_cloud();
    openvdb::FloatGrid::Ptr heat = cloud->deepCopy();
    heat->setName("temperature");
    openvdb::tools::foreach (heat->beginValueOn(), [](const openvdb::FloatGrid::ValueOnIter& it) {
        it.setValue(*it * 1000.f);
    });
    nanovdb::io::writeGrid(dir.file("cloud.nvdb"), nanovdb::openToNanoVDB(*cloud));
    write_vdb(dir.file("fire.vdb"), {cloud, heat});
    auto scene = [&](const std::string& medium) {
        return "LookAt 0 0 30 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\nAttributeBegin\n"
               "  Translate 1 0 0\n  Scale 2 2 2\n" +
               medium + "\nAttributeEnd\nMediumInterface \"c\" \"\"\nMaterial \"interface\"\n" +
               "Shape \"sphere\" \"float radius\" 20\n";
    };
    const Scene p = parse_pbrt_scene(
        scene(
            "MakeNamedMedium \"c\" \"string type\" \"nanovdb\" \"string filename\" \"cloud.nvdb\""),
        "t.pbrt", dir.path().string());
    REQUIRE(p.media.size() == 1);
    CHECK(p.media[0].kind == MediumKind::Grid);
    CHECK(p.media[0].density->box().lo.x == Approx(1.f + 2.f * (0.25f * -5.5f + 1.f)));
    CHECK(!p.media[0].emits());
    // pbrt-v4's defaults: sigma_a = sigma_s = 1.
    CHECK(p.media[0].sigma_a.g == 1.f);
    // The temperature grid glows: Le(p) = Lescale x blackbody((T(p) - offset) x scale).
    const std::string fire =
        "MakeNamedMedium \"c\" \"string type\" \"nanovdb\" \"string filename\" \"fire.vdb\" "
        "\"float Lescale\" 2 \"float temperatureoffset\" 100 \"float temperaturescale\" 1.5";
    const Scene f = parse_pbrt_scene(scene(fire), "t.pbrt", dir.path().string());
    const Medium& m = f.media[0];
    REQUIRE(m.temperature);
    CHECK(m.emits());
    int hot = 0;
    for (uint64_t i = 0; i < 2000; ++i) {
        const Vec3 w{-2.f + 8.f * rng::uniform(7, 1, i, 0), -6.f + 6.f * rng::uniform(7, 1, i, 1),
                     -2.f + 8.f * rng::uniform(7, 1, i, 2)};
        const float kelvin = (m.temperature->lookup(w) - 100.f) * 1.5f;
        const RGB expected = kelvin > 100.f ? pbrt::blackbody_emission_rgb(kelvin) * 2.f : RGB{0.f};
        const RGB got = m.emission_at(w);
        hot += kelvin > 100.f ? 1 : 0;
        CHECK(got.r == Approx(expected.r).epsilon(0.002).margin(1e-4));
        CHECK(got.g == Approx(expected.g).epsilon(0.002).margin(1e-4));
    }
    CHECK(hot > 100);
    const Scene off =
        parse_pbrt_scene(scene(fire + " \"float Lescale\" 0"), "t.pbrt", dir.path().string());
    CHECK(!off.media[0].temperature);
    // The XML form: the same glow from the same file.
    const Scene x = parse_scene(
        xml_with("<medium name=\"m\" type=\"vdb\" src=\"fire.vdb\" temperature=\"temperature\" "
                 "temperature_offset=\"100\" temperature_scale=\"1.5\" emission_scale=\"2\">"
                 "<sigma_a r=\"1\" g=\"1\" b=\"1\"/><transform><scale s=\"2\"/><translate x=\"1\" "
                 "y=\"0\" z=\"0\"/></transform></medium>"),
        "v.xml", dir.path().string());
    REQUIRE(x.media[0].temperature);
    const Vec3 c{2.f * (0.25f * 3.f + 1.f) + 1.f, 2.f * (0.25f * -2.f), 2.f * (0.25f * 5.f - 2.f)};
    CHECK(x.media[0].emission_at(c).r == Approx(m.emission_at(c).r));
    try {
        parse_scene(
            xml_with("<medium name=\"m\" type=\"vdb\" src=\"fire.vdb\" "
                     "temperature=\"temperature\"><sigma_s r=\"1\" g=\"1\" b=\"1\"/></medium>"),
            "v.xml", dir.path().string());
        FAIL("parsed");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("v.xml:2: a glowing medium needs absorption") !=
              std::string::npos);
    }
}

TEST_CASE(
    "blackbody glow: pbrt-v4's peak-normalised spectrum through the CIE 1931 tables, and a "
    "camera inside a block at 2000 K sees it",
    "[media][render]") {
    // The sum over 360..830 nm of Planck / peak times the CIE 1931 table, in linear sRGB,
    // computed independently (Python, the table linear between its 5 nm samples).
    const RGB at2000 = pbrt::blackbody_emission_rgb(2000.f);
    CHECK(at2000.r == Approx(13.0566).epsilon(0.001));
    CHECK(at2000.g == Approx(3.35248).epsilon(0.001));
    CHECK(at2000.b == Approx(0.106287).epsilon(0.01));
    test::TempDir dir;
    openvdb::initialize();
    openvdb::FloatGrid::Ptr dens = openvdb::FloatGrid::create(0.f),
                            temp = openvdb::FloatGrid::create(0.f);
    dens->setName("density");
    temp->setName("temperature");
    dens->fill(openvdb::CoordBBox({-24, -24, -24}, {23, 23, 23}), 1.f);
    temp->fill(openvdb::CoordBBox({-24, -24, -24}, {23, 23, 23}), 2000.f);
    write_vdb(dir.file("block.vdb"), {dens, temp});
    std::ofstream(dir.file("block.pbrt"))
        << "MakeNamedMedium \"fire\" \"string type\" \"nanovdb\" \"string filename\" "
           "\"block.vdb\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [0.5 0.5 0.5]\n"
           "MediumInterface \"\" \"fire\"\nLookAt 0 0 0  0 0 1  0 1 0\n"
           "Camera \"perspective\" \"float fov\" 30\nFilm \"rgb\" \"integer xresolution\" 8 "
           "\"integer yresolution\" 8\nIntegrator \"volpath\" \"integer maxdepth\" 100\n"
           "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0 0 0]\n"
           "Shape \"sphere\" \"float radius\" 1000\n";
    TestScene s(load_scene(dir.file("block.pbrt")));
    const Film film = render_test(s, 64 * test::effort(), 2, 3).film;
    const RGB mean = compare_images(film, film).mean_a;
    INFO(mean.r << " " << mean.g << " " << mean.b);
    // 24 units of absorption 1 to the nearest face: the glow everywhere.
    CHECK(mean.r == Approx(at2000.r).epsilon(0.02));
    CHECK(mean.g == Approx(at2000.g).epsilon(0.02));
}

TEST_CASE("vdb: the example smoke's .vdb and .nvdb hold the samples of its .raw", "[media][fast]") {
    const Scene raw = load_scene(test::source_path("scenes/smoke.xml"));
    REQUIRE(raw.media.size() == 1);
    const DensityGrid& r = *raw.media[0].density;
    // smoke.xml's box: -1..1, 0..2.5, -1..1; the files hold the unit cube.
    const Affine place = Affine::translate({-1.f, 0.f, -1.f}) * Affine::scale({2.f, 2.5f, 2.f});
    for (const char* file : {"scenes/meshes/smoke.vdb", "scenes/meshes/smoke.nvdb"}) {
        INFO(file);
        const auto v = read_vdb_density(test::source_path(file), "density", place);
        double worst = 0.0;
        for (uint64_t n = 0; n < 20000; ++n) {
            // Inside the raw box by more than half a cell (the faces fade differently: the raw
            // grid stops at its box, the VDB one fades over a padded voxel).
            const Vec3 u{rng::uniform(6, 1, n, 0), rng::uniform(6, 1, n, 1),
                         rng::uniform(6, 1, n, 2)};
            const Vec3 p{-1.f + 2.f * (0.02f + 0.96f * u.x), 2.5f * (0.02f + 0.96f * u.y),
                         -1.f + 2.f * (0.02f + 0.96f * u.z)};
            worst = std::max(worst, double(std::fabs(v->lookup(p) - r.lookup(p))));
        }
        CHECK(worst < 1e-5 * r.max_value());
    }
}
