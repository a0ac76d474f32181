// SPDX-License-Identifier: Apache-2.0
// Oracles: round trips against the original bytes; a zlib stream made by CPython's zlib (not
// libdeflate) that must inflate to its known text; the zlib header rule of RFC 1950; the blosc
// header layout of c-blosc 1.x; and serial results for the concurrent runs.

#include <vdb/Exceptions.h>
#include <vdb/io/Codecs.h>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace vdb::io {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes floatBytes(const std::vector<float>& values) {
    Bytes bytes(values.size() * sizeof(float));
    if (!bytes.empty())  // memcpy from an empty vector's null data() is undefined
        std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

// A linear ramp laid out like the voxels of 8^3 leaves (z fastest), as a level set of a plane
// would store it: the values a dense leaf typically holds, and compressible.
Bytes smoothBytes(size_t byteCount) {
    std::vector<float> values(byteCount / sizeof(float));
    for (size_t i = 0; i < values.size(); ++i) {
        const auto x = float(i >> 6), y = float((i >> 3) & 7), z = float(i & 7);
        values[i] = 0.1f * x + 0.05f * y - 0.025f * z - 0.3f;
    }
    Bytes bytes = floatBytes(values);
    bytes.resize(byteCount, 0x3f);
    return bytes;
}

Bytes randomBytes(size_t byteCount, uint32_t seed) {
    std::mt19937 rng(seed);
    Bytes bytes(byteCount);
    for (uint8_t& b : bytes) {
        b = uint8_t(rng());
    }
    return bytes;
}

Bytes constantBytes(size_t byteCount) {
    const float value = 0.75f;
    Bytes bytes(byteCount);
    for (size_t i = 0; i < byteCount; ++i) {
        bytes[i] = reinterpret_cast<const uint8_t*>(&value)[i % sizeof(float)];
    }
    return bytes;
}

// Every input the round-trip tests use: three kinds of data at 0, 1, 8, 2048 and 1 MiB bytes.
std::vector<Bytes> sampleInputs() {
    std::vector<Bytes> inputs;
    uint32_t seed = 7;
    for (const size_t n : {size_t(0), size_t(1), size_t(8), size_t(2048), size_t(1) << 20}) {
        inputs.push_back(randomBytes(n, seed++));
        inputs.push_back(constantBytes(n));
        inputs.push_back(smoothBytes(n));
    }
    return inputs;
}

uint32_t readU32(const Bytes& bytes, size_t at) {
    return uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 | uint32_t(bytes[at + 2]) << 16 |
           uint32_t(bytes[at + 3]) << 24;
}

Bytes fromHex(std::string_view hex) {
    Bytes bytes;
    for (size_t i = 0; i + 1 < hex.size(); i += 2) {
        bytes.push_back(uint8_t(std::stoi(std::string(hex.substr(i, 2)), nullptr, 16)));
    }
    return bytes;
}

// ---- zip ----------------------------------------------------------------------------------

TEST(ZipCodec, RoundTripsRandomConstantAndSmoothData) {
    for (const Bytes& input : sampleInputs()) {
        Bytes stream;
        const size_t written = zipCompress(input, stream);
        ASSERT_EQ(written, stream.size());
        Bytes back(input.size(), 0xcd);
        zipDecompress(stream, back);
        ASSERT_EQ(back, input) << "size " << input.size();
    }
}

TEST(ZipCodec, AppendsAfterExistingBytes) {
    const Bytes input = smoothBytes(2048);
    Bytes out = {1, 2, 3};
    const size_t written = zipCompress(input, out);
    ASSERT_EQ(out.size(), 3 + written);
    EXPECT_EQ(out[0], 1);
    Bytes back(input.size());
    zipDecompress(std::span(out).subspan(3), back);
    EXPECT_EQ(back, input);
}

TEST(ZipCodec, StreamHasValidZlibHeader) {
    for (const int level : {1, 6, 9, 12}) {
        Bytes stream;
        zipCompress(smoothBytes(2048), stream, level);
        ASSERT_GE(stream.size(), 2u);
        EXPECT_EQ(stream[0], 0x78) << "deflate, 32 KiB window";
        EXPECT_EQ((stream[0] * 256 + stream[1]) % 31, 0) << "RFC 1950 header check bits";
        EXPECT_EQ(stream[1] & 0x20, 0) << "no preset dictionary";
    }
    Bytes stream;
    zipCompress(smoothBytes(2048), stream);
    EXPECT_EQ(stream[1], 0x9c) << "the default level gives zlib's default header, as OpenVDB";
}

TEST(ZipCodec, SmoothLeafCompressesWell) {
    Bytes stream;
    zipCompress(smoothBytes(2048), stream);
    EXPECT_LT(stream.size(), 2048u / 2);
}

TEST(ZipCodec, InflatesStreamMadeByZlib) {
    // python3 -c "import zlib;print(zlib.compress(b'hello hello hello hello').hex())"
    const Bytes stream = fromHex("789ccb48cdc9c957c8402701680308b1");
    const std::string_view text = "hello hello hello hello";
    Bytes back(text.size());
    zipDecompress(stream, back);
    EXPECT_EQ(std::string_view(reinterpret_cast<const char*>(back.data()), back.size()), text);
}

TEST(ZipCodec, RejectsWrongSizeCorruptionAndTruncation) {
    const Bytes input = smoothBytes(2048);
    Bytes stream;
    zipCompress(input, stream);

    Bytes shorter(input.size() - 1), longer(input.size() + 1), exact(input.size());
    EXPECT_THROW(zipDecompress(stream, shorter), IoError);
    EXPECT_THROW(zipDecompress(stream, longer), IoError);
    Bytes nothing;
    EXPECT_THROW(zipDecompress(stream, nothing), IoError);

    for (size_t cut = 0; cut < stream.size(); cut += 1 + stream.size() / 40) {
        EXPECT_THROW(zipDecompress(std::span(stream).first(cut), exact), IoError) << cut;
    }
    EXPECT_THROW(zipDecompress({}, exact), IoError);

    Bytes badChecksum = stream;
    badChecksum.back() ^= 0x01;
    EXPECT_THROW(zipDecompress(badChecksum, exact), IoError);
    Bytes badHeader = stream;
    badHeader[1] ^= 0x01;
    EXPECT_THROW(zipDecompress(badHeader, exact), IoError);
}

TEST(ZipCodec, GarbageNeverCrashes) {
    std::mt19937 rng(1234);
    const Bytes input = smoothBytes(2048);
    Bytes stream;
    zipCompress(input, stream);
    Bytes dst(input.size());
    for (int trial = 0; trial < 3000; ++trial) {
        Bytes bytes = trial % 2 == 0 ? randomBytes(rng() % 65, rng()) : stream;
        if (trial % 2 == 1) {
            bytes[rng() % bytes.size()] ^= uint8_t(1 + rng() % 255);
        }
        try {
            zipDecompress(bytes, dst);
        } catch (const IoError&) {
        }
    }
}

TEST(ZipCodec, RejectsLevelsOutsideLibdeflateRange) {
    Bytes out;
    EXPECT_THROW(zipCompress(smoothBytes(8), out, 0), ValueError);
    EXPECT_THROW(zipCompress(smoothBytes(8), out, 13), ValueError);
    EXPECT_TRUE(out.empty());
}

// ---- blosc --------------------------------------------------------------------------------

TEST(BloscCodec, RoundTripsRandomConstantAndSmoothData) {
    for (const Bytes& input : sampleInputs()) {
        Bytes frame;
        const size_t written = bloscCompress(input, frame);
        ASSERT_GT(written, 0u) << "size " << input.size();
        ASSERT_EQ(written, frame.size());
        EXPECT_EQ(bloscDecompressedSize(frame), input.size());
        Bytes back(input.size(), 0xcd);
        bloscDecompress(frame, back);
        ASSERT_EQ(back, input) << "size " << input.size();
    }
}

TEST(BloscCodec, HeaderStatesVersionTypesizeAndSizes) {
    for (const Bytes& input : sampleInputs()) {
        Bytes frame;
        bloscCompress(input, frame);
        ASSERT_GE(frame.size(), 16u);
        EXPECT_EQ(frame[0], 2) << "format version";
        EXPECT_EQ(frame[3], 4) << "typesize 4 whatever the element type";
        EXPECT_EQ(readU32(frame, 4), input.size());
        EXPECT_EQ(readU32(frame, 12), frame.size());
    }
}

TEST(BloscCodec, EmptyInputGivesHeaderOnlyFrame) {
    Bytes frame;
    EXPECT_EQ(bloscCompress({}, frame), 16u);
    Bytes nothing;
    bloscDecompress(frame, nothing);
    EXPECT_EQ(bloscDecompressedSize(frame), 0u);
}

TEST(BloscCodec, TinyInputIsMemcpyed) {
    const Bytes input = smoothBytes(8);
    Bytes frame;
    bloscCompress(input, frame);
    EXPECT_NE(frame[2] & 0x02, 0) << "memcpyed flag";
    EXPECT_EQ(frame.size(), 16u + input.size());
    EXPECT_EQ(Bytes(frame.begin() + 16, frame.end()), input);
}

TEST(BloscCodec, SmoothLeafIsShuffledLz4AndSmaller) {
    const Bytes input = smoothBytes(2048);
    Bytes frame;
    bloscCompress(input, frame);
    EXPECT_EQ(frame[2] & 0x02, 0) << "not memcpyed";
    EXPECT_NE(frame[2] & 0x01, 0) << "byte shuffle";
    EXPECT_EQ(frame[2] >> 5, 1) << "lz4";
    EXPECT_EQ(readU32(frame, 8), input.size()) << "one block for the whole input";
    EXPECT_LT(frame.size(), input.size());
}

TEST(BloscCodec, AppendsAfterExistingBytes) {
    const Bytes input = smoothBytes(2048);
    Bytes out = {9, 9};
    const size_t written = bloscCompress(input, out);
    ASSERT_EQ(out.size(), 2 + written);
    Bytes back(input.size());
    bloscDecompress(std::span(out).subspan(2), back);
    EXPECT_EQ(back, input);
}

TEST(BloscCodec, AcceptsBytesAfterTheFrame) {
    const Bytes input = smoothBytes(2048);
    Bytes frame;
    bloscCompress(input, frame);
    frame.insert(frame.end(), {1, 2, 3, 4});
    Bytes back(input.size());
    bloscDecompress(frame, back);
    EXPECT_EQ(back, input);
}

TEST(BloscCodec, RejectsTruncatedFramesAndWrongSizes) {
    for (const Bytes& input : {smoothBytes(2048), smoothBytes(8), randomBytes(4096, 3)}) {
        Bytes frame;
        bloscCompress(input, frame);
        Bytes exact(input.size());
        for (size_t cut = 0; cut < frame.size(); cut += 1 + frame.size() / 50) {
            EXPECT_THROW(bloscDecompress(std::span(frame).first(cut), exact), IoError) << cut;
        }
        Bytes shorter(input.size() - 1), longer(input.size() + 1);
        EXPECT_THROW(bloscDecompress(frame, shorter), IoError);
        EXPECT_THROW(bloscDecompress(frame, longer), IoError);
    }
}

TEST(BloscCodec, DecompressedSizeRejectsShortOrInvalidHeaders) {
    Bytes frame;
    bloscCompress(smoothBytes(2048), frame);
    EXPECT_THROW(bloscDecompressedSize(std::span(frame).first(15)), IoError);
    EXPECT_EQ(bloscDecompressedSize(std::span(frame).first(16)), 2048u);
    Bytes badVersion = frame;
    badVersion[0] = 0;
    EXPECT_THROW(bloscDecompressedSize(badVersion), IoError);
    badVersion[0] = 0xff;
    EXPECT_THROW(bloscDecompressedSize(badVersion), IoError);
    Bytes badFrameSize = frame;
    badFrameSize[12] = 3;
    badFrameSize[13] = badFrameSize[14] = badFrameSize[15] = 0;
    EXPECT_THROW(bloscDecompressedSize(badFrameSize), IoError);
}

// Random bytes, random headers over random payloads, and random flips of valid frames must
// each give IoError or a decode of exactly dst.size() bytes; a crash fails the whole binary.
TEST(BloscCodec, GarbageNeverCrashes) {
    std::mt19937 rng(4321);
    Bytes valid;
    bloscCompress(smoothBytes(2048), valid);
    Bytes validSmall;
    bloscCompress(smoothBytes(40), validSmall);

    int decoded = 0;
    for (int trial = 0; trial < 6000; ++trial) {
        Bytes bytes;
        size_t dstSize = rng() % 96;
        switch (trial % 4) {
            case 0:
                bytes = randomBytes(rng() % 65, rng());
                break;
            case 1: {
                // A plausible header: right version, stated sizes consistent with the chunk.
                bytes = randomBytes(16 + rng() % 49, rng());
                bytes[0] = 2;
                dstSize = rng() % 300;
                const auto blocksize = uint32_t(1 + rng() % 300);
                for (int i = 0; i < 4; ++i) {
                    bytes[4 + i] = uint8_t(dstSize >> (8 * i));
                    bytes[8 + i] = uint8_t(blocksize >> (8 * i));
                    bytes[12 + i] = uint8_t(bytes.size() >> (8 * i));
                }
                break;
            }
            case 2:
                bytes = valid;
                dstSize = 2048;
                for (int flips = 1 + int(rng() % 3); flips > 0; --flips) {
                    bytes[rng() % bytes.size()] ^= uint8_t(1 + rng() % 255);
                }
                break;
            default:
                bytes = validSmall;
                dstSize = 40;
                bytes[rng() % bytes.size()] ^= uint8_t(1 + rng() % 255);
                break;
        }
        Bytes dst(dstSize);
        try {
            bloscDecompress(bytes, dst);
            ++decoded;
        } catch (const IoError&) {
        }
        try {
            (void)bloscDecompressedSize(bytes);
        } catch (const IoError&) {
        }
    }
    // Flips in the payload of a memcpyed frame still decode: the loop reached blosc itself.
    EXPECT_GT(decoded, 0);
}

// ---- threads ------------------------------------------------------------------------------

TEST(Codecs, ConcurrentCallsMatchSerialResults) {
    constexpr int N = 64;
    std::vector<Bytes> inputs(N);
    for (int i = 0; i < N; ++i) {
        inputs[i] = i % 3 == 0 ? randomBytes(512 * size_t(1 + i % 7), uint32_t(i))
                               : smoothBytes(2048 * size_t(1 + i % 5));
    }
    std::vector<Bytes> zipSerial(N), bloscSerial(N);
    for (int i = 0; i < N; ++i) {
        zipCompress(inputs[i], zipSerial[i], 1 + i % 12);
        bloscCompress(inputs[i], bloscSerial[i]);
    }

    for (int round = 0; round < 4; ++round) {
        std::vector<Bytes> zipParallel(N), bloscParallel(N);
        std::vector<int> ok(N, 0);
        tbb::parallel_for(0, N, [&](int i) {
            zipCompress(inputs[i], zipParallel[i], 1 + i % 12);
            bloscCompress(inputs[i], bloscParallel[i]);
            Bytes zipBack(inputs[i].size()), bloscBack(inputs[i].size());
            zipDecompress(zipSerial[i], zipBack);
            bloscDecompress(bloscSerial[i], bloscBack);
            ok[i] = zipBack == inputs[i] && bloscBack == inputs[i];
        });
        for (int i = 0; i < N; ++i) {
            ASSERT_EQ(zipParallel[i], zipSerial[i]) << i;
            ASSERT_EQ(bloscParallel[i], bloscSerial[i]) << i;
            ASSERT_TRUE(ok[i]) << i;
        }
    }
}

}  // namespace
}  // namespace vdb::io
