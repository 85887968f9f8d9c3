// `symphong compare`: options from compareSchema() (compare/compare.h); the metrics as a table or JSON,
// the error and FLIP maps as pictures.
#include "cli/commands.h"
#include "cli/schema_cli.h"
#include "compare/compare.h"

#include <fmt/format.h>

namespace symphong {

void addCompareCommand(CLI::App& app, CompareOptions& o) {
    CLI::App* c = app.add_subcommand("compare", "Measure an image against a reference: MSE, relMSE, bias, FLIP; error maps.");
    c->footer(
        "Images: OpenEXR, PFM and Radiance HDR are linear; PNG and JPEG are decoded through the sRGB curve to linear\n"
        "values. Every measure is of linear values: luminance Y = 0.2126 R + 0.7152 G + 0.0722 B and each channel.\n"
        "relMSE is the mean of (Y - Y_ref)^2 / (Y_ref^2 + 0.01); the ratio is mean(Y) / mean(Y_ref); the bias is\n"
        "mean(Y) - mean(Y_ref), with its standard error (and z) when --variance gives the test image's per-pixel\n"
        "variance of the mean (the reference counted as exact). FLIP is NVIDIA's perceptual error (Andersson et al.\n"
        "2020; HDR-FLIP 2021), 0 = identical, 1 = most different: LDR-FLIP when both images are 8-bit, HDR-FLIP\n"
        "otherwise, its exposure range from the reference. Exit code 2 on a missing, unreadable or mismatched image.\n"
        "Example: symphong compare out/test.exr ref.exr --regions 0,0,64,64 --error-map err.png --flip-map flip.png\n");
    addSchemaOptions(c, o, compareSchema());
    c->get_option("test")->required();
    c->get_option("reference")->required();
}

int runCompareCommand(const CompareOptions& o) {
    const Comparison c = runComparison(o);
    if (o.json)
        fmt::print("{}\n", comparisonJson(c, o).dump(1));
    else
        fmt::print("{}", comparisonText(c, o));
    return 0;
}

}  // namespace symphong
