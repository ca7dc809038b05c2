// The `foton` Python module: scenes loaded once and rendered with any settings, images and
// AOVs as NumPy arrays, the image metrics of `foton compare`. Errors in what the caller gave
// raise foton.InputError (a ValueError) with the command line's `file:line: problem`.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "engine/core/error.h"
#include "engine/film/image_io.h"
#include "engine/film/metrics.h"
#include "engine/film/ssim.h"
#include "py_convert.h"
#include "py_render.h"

namespace pyb = pybind11;
using namespace foton;

namespace {

// An image argument: a path to an EXR, a result, or a (height, width, 3) array.
Film image_of(const pyb::handle& h, const char* what) {
    if (pyb::isinstance<pyb::str>(h)) return read_exr(h.cast<std::string>());
    if (pyb::isinstance<py::PyResult>(h)) return py::to_film(h.cast<py::PyResult&>().image(), what);
    return py::to_film(h, what);
}

pyb::dict compare(const pyb::handle& a_in, const pyb::handle& b_in,
                  std::optional<float> exclude_above) {
    const Film a = image_of(a_in, "a");
    // A reference at an integer multiple of the size is box-filtered down, as --reference's.
    const Film b = fit_reference(image_of(b_in, "b"), a.width, a.height, "compare(b=)");
    // The command line's mask: the reference's (b's) pixels above the luminance, grown by one.
    std::vector<uint8_t> mask(a.pixels.size(), 1);
    if (exclude_above)
        mask = grow_exclusion(luminance_mask(b, *exclude_above), b.width, b.height, 1);
    const ImageError e = compare_images(a, b, &mask);
    pyb::dict d;
    d["rmse"] = e.rmse;
    d["relative_mse"] = e.relative_mse;
    d["mae"] = e.mae;
    d["max_abs"] = e.max_abs;
    d["ssim"] = ssim(a, b, &mask);
    d["pixels"] = e.pixels;
    d["mean_a"] = pyb::make_tuple(e.mean_a.r, e.mean_a.g, e.mean_a.b);
    d["mean_b"] = pyb::make_tuple(e.mean_b.r, e.mean_b.g, e.mean_b.b);
    return d;
}

}  // namespace

PYBIND11_MODULE(foton, m) {
    m.doc() = "foton, a research renderer for global illumination";
    static pyb::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
    pyb::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            PyErr_SetString(input_error.ptr(), e.what());
        }
    });

    pyb::class_<py::PyResult>(m, "Result", "A finished render")
        .def_property_readonly("image", &py::PyResult::image,
                               "linear RGB, a (height, width, 3) float32 array")
        .def_property_readonly("aovs", &py::PyResult::aovs,
                               "the AOVs asked for (aov=...): name -> (height, width[, channels])")
        .def_property_readonly("samples", &py::PyResult::samples,
                               "samples each pixel averages, (height, width) uint32")
        .def_property_readonly("stats", &py::PyResult::stats,
                               "the statistics of --stats-json, as a dict")
        .def_property_readonly("attributes", &py::PyResult::attributes,
                               "the EXR's string attributes (settings, seed, version, ...)")
        .def_property_readonly("spp", &py::PyResult::spp, "mean samples per pixel")
        .def_property_readonly("passes", &py::PyResult::passes)
        .def_property_readonly("seconds", &py::PyResult::seconds, "wall time of the render")
        .def("write_exr", &py::PyResult::write_exr, pyb::arg("path"),
             "writes the EXR foton render would (AOVs and metadata included)");

    pyb::class_<py::PyScene>(m, "Scene", "A scene file, loaded once")
        .def(pyb::init([](const std::string& path, const pyb::kwargs& settings) {
                 return py::PyScene(path, settings ? pyb::dict(settings) : pyb::dict());
             }),
             pyb::arg("path"))
        .def("render", &py::PyScene::render,
             "render(integrator=, spp=, passes=, time=, seed=, threads=, width=, height=, "
             "accel=, aov=, progress=callable(image, report), **settings) -> Result")
        .def_property_readonly("path", &py::PyScene::path)
        .def_property_readonly("width", &py::PyScene::width)
        .def_property_readonly("height", &py::PyScene::height);

    m.def(
        "load_scene",
        [](const std::string& path, const pyb::kwargs& settings) {
            return py::PyScene(path, settings ? pyb::dict(settings) : pyb::dict());
        },
        pyb::arg("path"),
        "loads a scene file (foton XML or pbrt-v4); keyword settings apply as --set does");
    m.def("compare", &compare, pyb::arg("a"), pyb::arg("b"),
          pyb::arg("exclude_above") = pyb::none(),
          "foton compare's figures (rmse, relative_mse, mae, max_abs, ssim, ...) of a against "
          "the reference b (box-filtered down when it is an integer multiple of a's size); "
          "each an EXR path, a Result or a (height, width, 3) array");
    m.def(
        "read_exr",
        [](const std::string& path,
           std::optional<std::vector<std::string>> channels) -> pyb::object {
            if (!channels) return py::to_array(read_exr(path));
            int w = 0, h = 0;
            AovLayer l{"", *channels, read_exr_channels(path, *channels, w, h)};
            return py::to_array(l, w, h);
        },
        pyb::arg("path"), pyb::arg("channels") = pyb::none(),
        "an EXR's R, G, B (or the named channels) as a float32 array");
}
