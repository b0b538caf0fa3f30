// brdfkit.render, brdfkit.tonemap and brdfkit.read_hdr (DESIGN §8): the preview renderer and
// the HDR pipeline, called as `brdf render` and `brdf tonemap` call them.
//
// Copies: a rendered or read image is handed to numpy without a copy (the array owns the
// library's buffer); tonemap copies its input into the library's Image (the pipeline works on
// its own copy anyway) and its 8-bit result is handed over without a copy.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/errors.h"
#include "hdr/image_files.h"
#include "hdr/pipeline.h"
#include "hdr/tone_arguments.h"
#include "models/model_source.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/errors.h"
#include "render/material.h"
#include "render/scene_lighting.h"
#include "render/sphere.h"

namespace brdf::python {
namespace {

// Moves `values` into a numpy array of `shape` that frees them when it is collected.
template <typename T>
py::array_t<T> Adopt(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule free_when_done(owned,
                             [](void* pointer) { delete static_cast<std::vector<T>*>(pointer); });
  return py::array_t<T>(shape, owned->data(), free_when_done);
}

py::array_t<float> ImageArray(Image&& image) {
  const py::ssize_t height = image.height, width = image.width;
  return Adopt(std::move(image.rgba), {height, width, py::ssize_t{Image::kChannels}});
}

// An (H, W, 4) or (H, W, 3) float array (alpha 1 when absent) as the library's Image.
Image ImageFromArray(const py::array_t<float, py::array::c_style | py::array::forcecast>& array) {
  if (array.ndim() != 3 || (array.shape(2) != 3 && array.shape(2) != 4)) {
    throw UsageError("image: expected an (H, W, 4) or (H, W, 3) float array, or a path");
  }
  CheckImageSize(static_cast<int>(array.shape(1)), static_cast<int>(array.shape(0)), "image");
  Image image(static_cast<int>(array.shape(1)), static_cast<int>(array.shape(0)));
  const py::ssize_t channels = array.shape(2);
  const float* in = array.data();
  for (int64_t pixel = 0; pixel < image.pixel_count(); ++pixel) {
    for (py::ssize_t c = 0; c < channels; ++c) {
      image.rgba[pixel * Image::kChannels + c] = in[pixel * channels + c];
    }
  }
  return image;
}

std::unique_ptr<Material> MaterialOf(const py::object& material) {
  if (py::isinstance<Model>(material)) return ModelMaterialOf(material.cast<Model>());
  if (py::isinstance<PythonFit>(material)) {
    return ModelMaterialOf(material.cast<const PythonFit&>().model_fit.fit.model);
  }
  if (py::isinstance<Measurement>(material)) {
    const auto measurement = material.cast<std::shared_ptr<Measurement>>();
    py::gil_scoped_release release;
    return MeasurementMaterialOf(*measurement);
  }
  if (py::isinstance<py::str>(material)) {
    const std::string spec = material.cast<std::string>();
    py::gil_scoped_release release;
    return LoadMaterial(spec);
  }
  throw UsageError(
      "material: expected a Model, FitResult, Measurement, model string or path, got " +
      py::repr(material).cast<std::string>());
}

}  // namespace

void RegisterImages(py::module_& module) {
  const RenderOptions render_defaults;
  module.def(
      "render",
      [](const py::object& material, const py::object& env, const py::object& light,
         const py::object& preset, int size, int spp, uint64_t seed, int threads) {
        RenderOptions options;
        options.size = size;
        options.spp = spp;
        options.seed = seed;
        options.Validate();
        const std::vector<std::string> lights = StringList(light, "light");
        const std::vector<std::string> presets = StringList(preset, "preset");
        const std::string environment = env.is_none() ? "" : env.cast<std::string>();
        std::unique_ptr<Material> resolved;
        std::optional<SceneLighting> lighting;
        RenderResult render;
        {
          const ThreadLimit limit(threads);
          resolved = MaterialOf(material);
          py::gil_scoped_release release;
          lighting = MakeSceneLighting(lights, presets, environment);
          render =
              RenderSphere(*resolved, lighting->lights, lighting->environment_or_null(), options);
        }
        for (const std::string& warning : lighting->warnings) Warn(warning);
        if (render.missing_lookups > 0) {
          Warn(resolved->Describe() + ": " + std::to_string(render.missing_lookups) +
               " lookups fell on missing data and were rendered black");
        }
        return ImageArray(std::move(render.radiance));
      },
      py::arg("material"), py::arg("env") = py::none(), py::arg("light") = py::none(),
      py::arg("preset") = py::none(), py::arg("size") = render_defaults.size,
      py::arg("spp") = render_defaults.spp, py::arg("seed") = render_defaults.seed,
      py::arg("threads") = 0, R"doc(
A preview sphere of a material, as `brdf render` computes it before tone mapping:
the same inputs and seed give the same floats as its `--exr FILE --exr-type float` output.

material: a Model, a FitResult (its model), a Measurement, or the CLI's MATERIAL text (model
          string, FIT.json or measurement file).
env:      environment: an equirectangular OpenEXR/Radiance file, or "uniform:L" (radiance in
          W/m^2/sr); importance sampled. Default None.
light:    directional light(s) "dir:theta=DEG:phi=DEG:lux=LX" (or irradiance=W/m^2, or
          rgb=R,G,B W/m^2): a str or a list of str. Default None.
preset:   illuminance preset name(s) (brdf render --help lists them), a str or list of str.
          With no light, preset or env, the "office" preset lights the sphere.
size:     image width and height in pixels (default 512).
spp:      environment samples per pixel and technique (default 64).
seed:     random seed (default 0); the same image for any thread count.
threads:  worker threads, 0 = all cores.

Returns float32 (size, size, 4): radiance in W/(m^2 sr) in RGB, alpha 1 on the sphere and 0
around it. The GIL is released while rendering.)doc");

  const ToneArguments tone_defaults;
  module.def(
      "tonemap",
      [](const py::object& image, const std::string& tone_operator, const py::object& exposure,
         const py::object& ev, double key, const py::object& white, const std::string& bloom,
         double bloom_threshold, double bloom_strength, double bloom_sigma,
         const py::object& gamma) {
        ToneArguments arguments;
        arguments.tone_operator = tone_operator;
        arguments.exposure = NumberOrAuto(exposure, "exposure");
        if (!ev.is_none()) {
          arguments.ev = ev.cast<double>();
          arguments.ev_given = true;
        }
        arguments.key = key;
        arguments.white = NumberOrAuto(white, "white");
        arguments.bloom = bloom;
        arguments.bloom_threshold = bloom_threshold;
        arguments.bloom_strength = bloom_strength;
        arguments.bloom_sigma = bloom_sigma;
        arguments.gamma = py::isinstance<py::str>(gamma) ? gamma.cast<std::string>()
                                                         : NumberOrAuto(gamma, "gamma");
        const ToneOptions options = arguments.Resolve();
        Image input;
        std::string name = "image";
        if (py::isinstance<py::str>(image)) {
          name = image.cast<std::string>();
          py::gil_scoped_release release;
          input = ReadHdrImage(name);
        } else {
          input = ImageFromArray(
              image.cast<py::array_t<float, py::array::c_style | py::array::forcecast>>());
        }
        ToneResult result;
        int64_t broken = 0;
        {
          py::gil_scoped_release release;
          broken = ReplaceNonFinite(&input);
          result = RunTonePipeline(input, options);
        }
        if (broken > 0) {
          Warn(name + ": " + std::to_string(broken) +
               " pixels with NaN or infinite values, replaced by 0");
        }
        for (const std::string& warning : result.warnings) Warn(name + ": " + warning);
        const py::ssize_t height = result.display.height, width = result.display.width;
        return Adopt(std::move(result.display.rgb), {height, width, py::ssize_t{3}});
      },
      py::arg("image"), py::arg("operator") = tone_defaults.tone_operator,
      py::arg("exposure") = tone_defaults.exposure, py::arg("ev") = py::none(),
      py::arg("key") = tone_defaults.key, py::arg("white") = tone_defaults.white,
      py::arg("bloom") = tone_defaults.bloom,
      py::arg("bloom_threshold") = tone_defaults.bloom_threshold,
      py::arg("bloom_strength") = tone_defaults.bloom_strength,
      py::arg("bloom_sigma") = tone_defaults.bloom_sigma, py::arg("gamma") = tone_defaults.gamma,
      R"doc(
The HDR pipeline, as `brdf tonemap` runs it: exposure -> bloom -> tone mapping on
luminance -> transfer curve -> 8 bits. The same image and options give the same bytes as the
pixels of its PNG.

image:           a float (H, W, 4) or (H, W, 3) array (e.g. from render), or the path of an
                 OpenEXR or Radiance image. NaN/Inf pixels become black, with a warning.
operator:        "exposure" (1 - exp(-x exposure)), "reinhard" (Reinhard 2002 global),
                 "reinhard-extended" (with L_white; default) or "none".
exposure:        "auto" (default: the log-average luminance goes to `key`) or a multiplier.
ev:              exposure value instead: the multiplier is 2^ev (not with `exposure`).
key:             Reinhard's key a, the grey the log-average maps to (default 0.18).
white:           reinhard-extended L_white in key-scaled units (Reinhard 2002 eq. 4); "auto"
                 (default) = the scene maximum, which then maps to 1.
bloom:           "none" (default), "box", "gauss", "kawase" or "dual" (Bjorge 2015).
bloom_threshold: luminance after exposure above which light blooms (default 1).
bloom_strength:  weight of the blurred bright pass added back (default 0.1).
bloom_sigma:     blur standard deviation in pixels (default 13; dual rounds to whole levels).
gamma:           "srgb" (IEC 61966-2-1; default) or a plain gamma such as 2.2 or 1.

Returns uint8 (H, W, 3), sRGB-encoded.)doc");

  module.def(
      "read_hdr",
      [](const std::string& path) {
        Image image;
        {
          py::gil_scoped_release release;
          image = ReadHdrImage(path);
        }
        return ImageArray(std::move(image));
      },
      py::arg("path"), R"doc(
Reads an OpenEXR (.exr) or Radiance (.hdr) image as `brdf tonemap` does: float32 (H, W, 4),
linear RGB plus alpha, rows top to bottom. Raises InputError for a broken file.)doc");
}

}  // namespace brdf::python
