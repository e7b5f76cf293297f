// flash_file.h - motorsim's flash: the configuration store's two sectors
// (firmware/config/flash_if.h) kept in a file, so that a simulated drive
// keeps its saved parameters across runs (--flash-image PATH). It behaves
// as the STM32F405's sectors do for the store: an erase sets every word to
// 0xFFFFFFFF, a program only clears bits (a word asked to set one is
// refused: the store never asks); after each erase or program the whole
// image is written to PATH.tmp and renamed over PATH, so a motorsim killed
// mid-write leaves the old image or the new one. A missing file is a new
// board (both sectors erased); a file of another size is refused naming
// it.
#ifndef MCSIM_MOTORSIM_FLASH_FILE_H
#define MCSIM_MOTORSIM_FLASH_FILE_H

#include <cstdint>
#include <string>
#include <vector>

extern "C" {
#include "config/flash_if.h"
}

namespace mcsim {

class FlashFile {
public:
    // The STM32F405 store's sector size (sectors 1 and 2: 16 KB each).
    static constexpr std::uint32_t kSectorWords = 4096;

    // Reads path (absent: erased). Throws std::invalid_argument naming the
    // file when it is not an image of two sectors (a directory, another
    // size), std::runtime_error when it cannot be read.
    explicit FlashFile(std::string path);

    // The interface the store is given (it points into this object).
    flash_if_t interface();

    const std::string& path() const { return path_; }
    bool existed() const { return existed_; }

private:
    static flash_if_result_t erase_op(void* ctx, std::uint32_t sector);
    static flash_if_result_t program_op(void* ctx, std::uint32_t sector, std::uint32_t offset,
                                        const std::uint32_t* words, std::uint32_t n);
    static const char* error_op(void* ctx);
    bool write_back();

    std::string path_;
    bool existed_ = false;
    std::vector<std::uint32_t> mem_[FLASH_IF_SECTORS];
    std::string error_;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_FLASH_FILE_H
