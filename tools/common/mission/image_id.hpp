/**
 * @file image_id.hpp
 * @brief The identity of a mission image build: its ELF build ID, which a copy of the file keeps.
 *
 * The world cache keys its products by it, and a campaign folder records it, so that runs of one
 * build share a world and a resumed campaign is flown by the build that started it. A copy of the
 * image (another path, another modification time) is the same build; a relinked image with other
 * code is not. A file without a GNU build-ID note falls back to "size@mtime" (the older key).
 */
#pragma once

#include <string>

namespace tools {

/** "gnu-" and the build ID in hex, or "<size>@<mtime>" without one; "" if @p path cannot be read. */
std::string image_identity(const std::string& path);

/** image_identity() of the running program (/proc/self/exe). */
std::string own_image_identity();

}  // namespace tools
