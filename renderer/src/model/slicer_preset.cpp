// 3D Slicer presets.xml in (slicer_preset.h): the <VolumeProperty> elements' attributes, nothing else of XML.
#include "renderer/model/slicer_preset.h"

#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace renderer {

namespace {

constexpr std::string_view kElement = "<VolumeProperty";
constexpr size_t kMaxFileBytes = 16u << 20; // Slicer's own file is 12 kB; anything this big is not one

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool isNameChar(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == ':' || c == '-' || c == '.';
}

// The five predefined XML entities; anything else after '&' is kept as written.
std::string decodeEntities(std::string_view raw) {
    static const std::pair<std::string_view, char> entities[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    std::string out;
    for (size_t i = 0; i < raw.size(); ++i) {
        bool decoded = false;
        for (const auto& [entity, c] : entities)
            if (raw.substr(i, entity.size()) == entity) {
                out += c, i += entity.size() - 1, decoded = true;
                break;
            }
        if (!decoded) out += raw[i];
    }
    return out;
}

// One element's attributes, read from just after its tag name up to its closing '>' or '/>'.
// `where` names the element in errors ("VolumeProperty 3").
std::map<std::string, std::string> readAttributes(std::string_view text, size_t& pos,
                                                  const std::string& source, const std::string& where) {
    std::map<std::string, std::string> attributes;
    for (;;) {
        while (pos < text.size() && isSpace(text[pos]))
            ++pos;
        if (pos >= text.size())
            throw LoadError(source, where, "the element never ends, expected '>' or '/>'");
        if (text[pos] == '>') return ++pos, attributes;
        if (text.substr(pos, 2) == "/>") return pos += 2, attributes;
        const size_t nameStart = pos;
        while (pos < text.size() && isNameChar(text[pos]))
            ++pos;
        if (pos == nameStart)
            throw LoadError(source, where,
                            "'" + std::string(text.substr(pos, 20)) + "', expected an attribute name");
        const std::string name(text.substr(nameStart, pos - nameStart));
        while (pos < text.size() && isSpace(text[pos]))
            ++pos;
        if (pos >= text.size() || text[pos] != '=')
            throw LoadError(source, where + "." + name, "expected '=' and a quoted value after the name");
        ++pos;
        while (pos < text.size() && isSpace(text[pos]))
            ++pos;
        if (pos >= text.size() || (text[pos] != '"' && text[pos] != '\''))
            throw LoadError(source, where + "." + name, "expected a quoted value");
        const char quote = text[pos++];
        const size_t end = text.find(quote, pos);
        if (end == std::string_view::npos)
            throw LoadError(source, where + "." + name, "the quoted value never ends");
        attributes.emplace(name, decodeEntities(text.substr(pos, end - pos)));
        pos = end + 1;
    }
}

// "N v1 v2 ...": N numbers after the count, in groups of `stride` (at least one group), each finite.
std::vector<double> countedNumbers(const std::string& attribute, size_t stride, const char* groupMeaning,
                                   const std::string& source, const std::string& field) {
    std::vector<double> numbers;
    const char* p = attribute.data();
    const char* const end = p + attribute.size();
    for (;;) {
        while (p < end && isSpace(*p))
            ++p;
        if (p == end) break;
        double x = 0.0;
        const auto [next, ec] = std::from_chars(p, end, x);
        const char* wordEnd = p;
        while (wordEnd < end && !isSpace(*wordEnd))
            ++wordEnd;
        if (ec != std::errc() || next != wordEnd || !std::isfinite(x))
            throw LoadError(source, field,
                            "'" + std::string(p, wordEnd) + "' (number " +
                                std::to_string(numbers.size() + 1) + "), expected a finite number");
        numbers.push_back(x);
        p = next;
    }
    const std::string expected = "expected a count N, then N numbers in groups of " + std::to_string(stride) +
                                 " (" + groupMeaning + ")";
    if (numbers.empty()) throw LoadError(source, field, "empty, " + expected);
    const double count = numbers.front();
    numbers.erase(numbers.begin());
    if (count != std::floor(count) || count < double(stride) || std::fmod(count, double(stride)) != 0.0)
        throw LoadError(source, field, "count " + std::to_string(count) + ", " + expected);
    if (double(numbers.size()) != count)
        throw LoadError(source, field,
                        "count " + std::to_string(size_t(count)) + " but " + std::to_string(numbers.size()) +
                            " numbers follow it; " + expected);
    return numbers;
}

// Positions (every `stride`-th number) never decrease; values after them in [0,1].
void checkPoints(const std::vector<double>& numbers, size_t stride, const std::string& source,
                 const std::string& field) {
    for (size_t i = 0; i < numbers.size(); i += stride) {
        if (i > 0 && numbers[i] < numbers[i - stride])
            throw LoadError(source, field,
                            "position " + std::to_string(numbers[i]) + " after " +
                                std::to_string(numbers[i - stride]) +
                                ", expected positions in increasing order");
        for (size_t c = 1; c < stride; ++c)
            if (numbers[i + c] < 0.0 || numbers[i + c] > 1.0)
                throw LoadError(source, field,
                                std::to_string(numbers[i + c]) + " at position " +
                                    std::to_string(numbers[i]) + ", expected [0,1]");
    }
}

SlicerPreset presetFromAttributes(const std::map<std::string, std::string>& attributes,
                                  const std::string& source, const std::string& where) {
    std::string named = where; // errors name the preset once its name is known
    const auto get = [&](const std::string& key) -> const std::string& {
        const auto it = attributes.find(key);
        if (it == attributes.end()) throw LoadError(source, named + "." + key, "missing");
        return it->second;
    };
    SlicerPreset preset;
    preset.tf.name = get("name");
    if (preset.tf.name.empty()) throw LoadError(source, where + ".name", "empty, expected the preset's name");
    named = preset.tf.name;
    const std::string field = named + ".";
    const std::vector<double> opacity =
        countedNumbers(get("scalarOpacity"), 2, "value, opacity", source, field + "scalarOpacity");
    checkPoints(opacity, 2, source, field + "scalarOpacity");
    for (size_t i = 0; i < opacity.size(); i += 2)
        preset.tf.opacities.push_back({opacity[i], opacity[i + 1]});
    const std::vector<double> colour =
        countedNumbers(get("colorTransfer"), 4, "value, red, green, blue", source, field + "colorTransfer");
    checkPoints(colour, 4, source, field + "colorTransfer");
    for (size_t i = 0; i < colour.size(); i += 4)
        preset.tf.colours.push_back({colour[i], {colour[i + 1], colour[i + 2], colour[i + 3]}});
    if (attributes.contains("gradientOpacity")) {
        const std::vector<double> gradient =
            countedNumbers(attributes.at("gradientOpacity"), 2, "gradient magnitude, opacity", source,
                           field + "gradientOpacity");
        checkPoints(gradient, 2, source, field + "gradientOpacity");
        bool allOne = true;
        for (size_t i = 0; i < gradient.size(); i += 2) {
            preset.tf.gradientOpacity.push_back({gradient[i], gradient[i + 1]});
            allOne = allOne && gradient[i + 1] == 1.0;
        }
        if (allOne) preset.tf.gradientOpacity.clear(); // the same image, and a file without the field
    }
    return preset;
}

std::string readSmallTextFile(const std::filesystem::path& path) {
    requireRegularFile(path, "3D Slicer volume-rendering presets (.xml)"); // a FIFO would block the read
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes > kMaxFileBytes)
        throw LoadError(path.string(), "",
                        std::to_string(bytes) + " bytes, expected a presets file under " +
                            std::to_string(kMaxFileBytes >> 20) + " MB");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw LoadError(path.string(), "", "cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw LoadError(path.string(), "", "cannot read");
    return text.str();
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

} // namespace

std::vector<SlicerPreset> slicerPresetsFromXml(std::string_view text, const std::string& source) {
    std::vector<SlicerPreset> presets;
    size_t pos = 0;
    while (pos < text.size()) {
        const size_t element = text.find(kElement, pos), comment = text.find("<!--", pos);
        if (comment < element) { // a commented-out preset is not one
            const size_t end = text.find("-->", comment + 4);
            if (end == std::string_view::npos) break;
            pos = end + 3;
            continue;
        }
        if (element == std::string_view::npos) break;
        pos = element + kElement.size();
        if (pos < text.size() && !isSpace(text[pos]) && text[pos] != '/' && text[pos] != '>')
            continue; // a longer tag
        const std::string where = "VolumeProperty " + std::to_string(presets.size() + 1);
        presets.push_back(presetFromAttributes(readAttributes(text, pos, source, where), source, where));
    }
    if (presets.empty())
        throw LoadError(source, "",
                        "no <VolumeProperty> element, expected 3D Slicer volume-rendering presets");
    return presets;
}

std::vector<SlicerPreset> loadSlicerPresets(const std::filesystem::path& path) {
    return slicerPresetsFromXml(readSmallTextFile(path), path.string());
}

std::optional<SlicerPresetSpec> slicerPresetSpec(const std::string& spec) {
    if (lower(spec).ends_with(".xml")) return SlicerPresetSpec{spec, ""};
    const size_t hash = lower(spec).find(".xml#"); // the name may hold '#' itself
    if (hash == std::string::npos) return std::nullopt;
    return SlicerPresetSpec{spec.substr(0, hash + 4), spec.substr(hash + 5)};
}

LoadedSlicerPreset loadSlicerPreset(const SlicerPresetSpec& spec) {
    std::vector<SlicerPreset> presets = loadSlicerPresets(spec.file);
    const std::string file = spec.file.string();
    LoadedSlicerPreset loaded;
    if (spec.name.empty()) {
        loaded.preset = std::move(presets.front());
        if (presets.size() > 1)
            loaded.notes.push_back(file + " holds " + std::to_string(presets.size()) +
                                   " presets; took the first, " + loaded.preset.tf.name +
                                   " (pick another with " + file + "#NAME)");
    } else {
        const auto it = std::find_if(presets.begin(), presets.end(),
                                     [&](const SlicerPreset& p) { return p.tf.name == spec.name; });
        if (it == presets.end()) {
            std::string known;
            for (const SlicerPreset& p : presets)
                known += (known.empty() ? "" : ", ") + p.tf.name;
            throw LoadError(file, "", "no preset named '" + spec.name + "' (it holds: " + known + ")");
        }
        loaded.preset = std::move(*it);
    }
    return loaded;
}

} // namespace renderer
