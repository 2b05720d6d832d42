// The keys of [output] and of each [[probe]] as data (case_schema.hpp): what a run writes; and
// those of [stability], what `thermocontact stability` computes and writes.
#include "tc/io/schema/case_schema_parts.hpp"

namespace tc::io::schema {

namespace {

using T = Type;

constexpr std::string_view kOutputFormats[] = {"ascii", "binary", "vtkhdf"};
constexpr std::string_view kCompressions[] = {"none", "zlib"};

constexpr Key kOutput[] = {
    {.name = "directory",
     .type = T::string,
     .default_value = "\"out\"",
     .doc = "relative to the case file unless absolute"},
    {.name = "every",
     .type = T::integer,
     .default_value = "1",
     .doc = "fields every n steps (history.csv gets every step)"},
    {.name = "format",
     .type = T::choice,
     .choices = kOutputFormats,
     .default_value = "\"ascii\"",
     .doc = ".vtu arrays as text, or appended raw binary; or one VTKHDF file per body and step "
            "(parallel HDF5)"},
    {.name = "compression",
     .type = T::choice,
     .choices = kCompressions,
     .default_value = "\"none\"",
     .doc = "zlib-compressed binary arrays (implies format = \"binary\")"},
    {.name = "contact_csv",
     .type = T::boolean,
     .default_value = "false",
     .doc = "contact_<step>.csv of the contact nodes at each written step"},
    {.name = "checkpoint_every",
     .type = T::integer,
     .min = 0,
     .default_value = "0",
     .doc = "checkpoint.bin after every n steps (0: not by count)"},
    {.name = "checkpoint_seconds",
     .type = T::number,
     .range = from_zero("checkpoint_seconds (s) ≥ 0"),
     .default_value = "10.0",
     .unit = "s",
     .doc = "checkpoint.bin every s of wall time (0: not by time)"},
};

constexpr Key kProbe[] = {
    {.name = "name",
     .type = T::string,
     .default_value = "required",
     .doc = "prefix of its probes.csv columns: letters, digits, '_'"},
    {.name = "body", .type = T::name, .default_value = "required", .doc = "the body it is in"},
    {.name = "point",
     .type = T::vector,
     .unit = "m",
     .doc = "where, in the reference configuration (or where)"},
    {.name = "where", .type = T::name, .doc = "a boundary of the body: the mean over its nodes"},
};

constexpr std::string_view kNormalControls[] = {"displacement", "force"};

constexpr Key kStability[] = {
    {.name = "speeds",
     .type = T::numbers,
     .range = above_zero("a speed > 0"),
     .default_value = "none",
     .unit = "m/s",
     .doc = "the tool's sliding speeds analysed (none: the case's own after the state)",
     .expected = "a non-empty array of speeds > 0"},
    {.name = "eigenvalues",
     .type = T::integer,
     .min = 1,
     .max = 100,
     .default_value = "4",
     .doc = "the leading eigenvalues (growth rates) reported per speed"},
    {.name = "critical_speed",
     .type = T::boolean,
     .default_value = "true",
     .doc = "the speed at which the leading growth rate crosses 0"},
    {.name = "modes",
     .type = T::boolean,
     .default_value = "true",
     .doc = "the leading mode of each speed as .vtu"},
    {.name = "normal_control",
     .type = T::choice,
     .choices = kNormalControls,
     .default_value = "\"displacement\"",
     .doc = "the tool's normal motion in the perturbation: held as the case moves it, or free "
            "under its normal force (the mean pressure held)"},
    {.name = "friction_shear",
     .type = T::boolean,
     .default_value = "true",
     .doc = "the shear 𝔉λ_n of sliding in the perturbed mechanics (false: left out, as the "
            "classical closed form does)"},
    {.name = "target",
     .type = T::number,
     .default_value = "none",
     .unit = "1/s",
     .doc = "the shift σ of shift-and-invert (none: κ(ΛV)², Λ = 𝔉Eα/(k(1 − ν)))"},
    {.name = "state_step",
     .type = T::integer,
     .min = 1,
     .default_value = "1",
     .doc = "the step of the case whose state is linearised (≤ the case's steps)"},
};

}  // namespace

std::span<const Key> stability_keys() {
  return kStability;
}

std::span<const Key> output_keys() {
  return kOutput;
}

std::span<const Key> probe_keys() {
  return kProbe;
}

}  // namespace tc::io::schema
