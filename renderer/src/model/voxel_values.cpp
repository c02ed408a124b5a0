// Voxel values in their file's type (voxel_values.h).
#include "renderer/model/voxel_values.h"

namespace renderer {

const char* voxelTypeName(VoxelType t) {
    switch (t) {
    case VoxelType::U8: return "uint8";
    case VoxelType::U16: return "uint16";
    case VoxelType::I16: return "int16";
    case VoxelType::F32: return "float32";
    }
    return "unknown";
}

size_t voxelTypeBytes(VoxelType t) {
    switch (t) {
    case VoxelType::U8: return 1;
    case VoxelType::U16: return 2;
    case VoxelType::I16: return 2;
    case VoxelType::F32: return 4;
    }
    return 0;
}

VoxelValues VoxelValues::zeros(VoxelType type, size_t count) {
    switch (type) {
    case VoxelType::U8: return std::vector<uint8_t>(count, 0);
    case VoxelType::U16: return std::vector<uint16_t>(count, 0);
    case VoxelType::I16: return std::vector<int16_t>(count, 0);
    case VoxelType::F32: break;
    }
    return std::vector<float>(count, 0.0f);
}

std::vector<float>& VoxelValues::floats() {
    if (type() != VoxelType::F32) {
        std::vector<float> converted(size());
        visit([&](const auto& v) {
            for (size_t i = 0; i < v.size(); ++i) converted[i] = float(v[i]);
        });
        m_values = std::move(converted);
    }
    return std::get<std::vector<float>>(m_values);
}

} // namespace renderer
