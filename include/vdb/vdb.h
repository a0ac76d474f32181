// SPDX-License-Identifier: Apache-2.0
/// @file
/// Umbrella header: grids, trees, accessors, iterators, leaf manager, math and `.vdb` files
/// (io::File). Tools live in
/// <vdb/tools/NAME.h> and are included one by one.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Metadata.h>
#include <vdb/TypeName.h>
#include <vdb/Types.h>
#include <vdb/io/File.h>
#include <vdb/math/BBox.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Mat4.h>
#include <vdb/math/Ray.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/BitMask.h>
