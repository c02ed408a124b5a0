// A volume's voxel values in the type its file stores them: a uint8 scan takes one byte a voxel, not a
// float's four, from the reader to the scene builder (a 629 MB uint8 volume once took 4.9 GB to open).
// Each value reads as a float in the data's own units; loops over every voxel visit the typed vector.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <utility>
#include <variant>
#include <vector>

namespace renderer {

enum class VoxelType { U8, U16, I16, F32 };

const char* voxelTypeName(VoxelType t);       // "uint8", "uint16", "int16", "float32"
size_t voxelTypeBytes(VoxelType t);

class VoxelValues {
  public:
    VoxelValues() = default;
    VoxelValues(std::vector<float> v) : m_values(std::move(v)) {}
    VoxelValues(std::vector<uint8_t> v) : m_values(std::move(v)) {}
    VoxelValues(std::vector<uint16_t> v) : m_values(std::move(v)) {}
    VoxelValues(std::vector<int16_t> v) : m_values(std::move(v)) {}
    VoxelValues(std::initializer_list<float> v) : m_values(std::vector<float>(v)) {}
    // `count` zeros of `type`: what a reader fills.
    static VoxelValues zeros(VoxelType type, size_t count);

    VoxelType type() const { return VoxelType(m_values.index()); }
    size_t size() const {
        return std::visit([](const auto& v) { return v.size(); }, m_values);
    }
    bool empty() const { return size() == 0; }
    size_t bytes() const { return size() * voxelTypeBytes(type()); }
    float operator[](size_t i) const {
        switch (type()) {
        case VoxelType::U8: return float(std::get<std::vector<uint8_t>>(m_values)[i]);
        case VoxelType::U16: return float(std::get<std::vector<uint16_t>>(m_values)[i]);
        case VoxelType::I16: return float(std::get<std::vector<int16_t>>(m_values)[i]);
        case VoxelType::F32: break;
        }
        return std::get<std::vector<float>>(m_values)[i];
    }
    // Calls f with the typed vector (const std::vector<T>&): one dispatch for a loop over every voxel.
    template <class F> decltype(auto) visit(F&& f) const { return std::visit(std::forward<F>(f), m_values); }
    template <class F> decltype(auto) visit(F&& f) { return std::visit(std::forward<F>(f), m_values); }
    // The values as floats to write in place (volumes made in code, a rescaled NIfTI). Values of another
    // type are converted first, which takes a float a voxel: readers never call it on integer data.
    std::vector<float>& floats();

    bool operator==(const VoxelValues&) const = default;

  private:
    // In VoxelType's order, so the index is the type.
    std::variant<std::vector<uint8_t>, std::vector<uint16_t>, std::vector<int16_t>, std::vector<float>> m_values{
        std::in_place_index<3>};
};

} // namespace renderer
