// The keys of [output] and of each [[probe]] as data (case_schema.hpp): what a run writes.
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

}  // namespace

std::span<const Key> output_keys() {
  return kOutput;
}

std::span<const Key> probe_keys() {
  return kProbe;
}

}  // namespace tc::io::schema
