#include "motorsim/flash_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace mcsim {

namespace {
constexpr std::size_t kImageBytes = static_cast<std::size_t>(FLASH_IF_SECTORS) * FlashFile::kSectorWords * 4u;
}

FlashFile::FlashFile(std::string path) : path_(std::move(path))
{
    for (auto& m : mem_) {
        m.assign(kSectorWords, FLASH_IF_ERASED);
    }
    std::error_code ec;
    if (std::filesystem::is_directory(path_, ec)) {
        throw std::invalid_argument("--flash-image: " + path_ + ": is a directory, not a flash image");
    }
    std::ifstream f(path_, std::ios::binary);
    if (!f) {
        if (errno != ENOENT) {
            throw std::runtime_error("--flash-image: " + path_ + ": cannot be read: " + std::strerror(errno));
        }
        return;  // a new board
    }
    existed_ = true;
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (bytes.size() != kImageBytes) {
        throw std::invalid_argument("--flash-image: " + path_ + ": " + std::to_string(bytes.size()) +
                                    " bytes, not a flash image (" + std::to_string(kImageBytes) +
                                    " bytes: two sectors of 16 KB)");
    }
    for (std::uint32_t s = 0; s < FLASH_IF_SECTORS; ++s) {
        for (std::uint32_t i = 0; i < kSectorWords; ++i) {
            const unsigned char* b = &bytes[(static_cast<std::size_t>(s) * kSectorWords + i) * 4u];
            // little-endian, as the F405's flash reads
            mem_[s][i] = static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
                         (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
        }
    }
}

flash_if_t FlashFile::interface()
{
    flash_if_t f{};
    f.ctx = this;
    f.sector_words = kSectorWords;
    for (std::uint32_t s = 0; s < FLASH_IF_SECTORS; ++s) {
        f.base[s] = mem_[s].data();
    }
    f.erase = &FlashFile::erase_op;
    f.program = &FlashFile::program_op;
    f.error = &FlashFile::error_op;
    return f;
}

bool FlashFile::write_back()
{
    std::vector<unsigned char> bytes(kImageBytes);
    for (std::uint32_t s = 0; s < FLASH_IF_SECTORS; ++s) {
        for (std::uint32_t i = 0; i < kSectorWords; ++i) {
            unsigned char* b = &bytes[(static_cast<std::size_t>(s) * kSectorWords + i) * 4u];
            const std::uint32_t w = mem_[s][i];
            b[0] = static_cast<unsigned char>(w);
            b[1] = static_cast<unsigned char>(w >> 8);
            b[2] = static_cast<unsigned char>(w >> 16);
            b[3] = static_cast<unsigned char>(w >> 24);
        }
    }
    const std::string tmp = path_ + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) {
        error_ = tmp + ": " + std::strerror(errno);
        return false;
    }
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    if (std::fclose(f) != 0 || !ok) {
        error_ = tmp + ": write failed";
        std::remove(tmp.c_str());
        return false;
    }
    if (std::rename(tmp.c_str(), path_.c_str()) != 0) {
        error_ = path_ + ": " + std::strerror(errno);
        std::remove(tmp.c_str());
        return false;
    }
    return true;
}

flash_if_result_t FlashFile::erase_op(void* ctx, std::uint32_t sector)
{
    auto* f = static_cast<FlashFile*>(ctx);
    if (sector >= FLASH_IF_SECTORS) {
        f->error_ = "no such sector";
        return FLASH_IF_FAILED;
    }
    f->mem_[sector].assign(kSectorWords, FLASH_IF_ERASED);
    return f->write_back() ? FLASH_IF_OK : FLASH_IF_FAILED;
}

flash_if_result_t FlashFile::program_op(void* ctx, std::uint32_t sector, std::uint32_t offset,
                                        const std::uint32_t* words, std::uint32_t n)
{
    auto* f = static_cast<FlashFile*>(ctx);
    if (sector >= FLASH_IF_SECTORS || offset > kSectorWords || n > kSectorWords - offset) {
        f->error_ = "program outside the sector";
        return FLASH_IF_FAILED;
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        if ((words[i] & ~f->mem_[sector][offset + i]) != 0u) {
            f->error_ = "a program asked a bit from 0 to 1 (the word was not erased)";
            return FLASH_IF_FAILED;
        }
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        f->mem_[sector][offset + i] &= words[i];
    }
    return f->write_back() ? FLASH_IF_OK : FLASH_IF_FAILED;
}

const char* FlashFile::error_op(void* ctx) { return static_cast<FlashFile*>(ctx)->error_.c_str(); }

}  // namespace mcsim
