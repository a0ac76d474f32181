// SPDX-License-Identifier: Apache-2.0
// hello_grid: writes a few voxels into a sparse tree through an accessor, reads
// them back, and exits non-zero if anything reads back wrong.

#include <vdb/vdb.h>

#include <iostream>
#include <iterator>

int main() {
    const float background = 0.0f;
    vdb::FloatTree tree(background);
    vdb::tree::ValueAccessor<vdb::FloatTree> acc(tree);

    // Voxels far apart land in different leaves; negative coordinates are no special case.
    const vdb::Coord voxels[] = {vdb::Coord(0, 0, 0), vdb::Coord(1, 2, 3),
                                 vdb::Coord(-100, 7, 1000), vdb::Coord(4096, -4096, 12)};
    float value = 1.0f;
    for (const vdb::Coord& ijk : voxels) {
        acc.setValue(ijk, value);
        value += 1.0f;
    }

    int failures = 0;
    value = 1.0f;
    for (const vdb::Coord& ijk : voxels) {
        if (acc.getValue(ijk) != value || !acc.isValueOn(ijk)) {
            std::cerr << "voxel " << ijk << ": read " << acc.getValue(ijk) << ", expected " << value
                      << " and active\n";
            ++failures;
        }
        value += 1.0f;
    }

    // A voxel never written reads as the background and is inactive.
    const vdb::Coord untouched(5, 5, 5);
    if (tree.getValue(untouched) != background || tree.isValueOn(untouched)) {
        std::cerr << "voxel " << untouched << " should be inactive background\n";
        ++failures;
    }

    const auto activeCount = tree.activeVoxelCount();
    std::cout << "active voxels: " << activeCount << ", leaves: " << tree.leafCount() << '\n';
    if (activeCount != std::size(voxels)) {
        std::cerr << "expected " << std::size(voxels) << " active voxels\n";
        ++failures;
    }
    return failures == 0 ? 0 : 1;
}
