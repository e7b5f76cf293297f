// sim_flash.h - a simulated NOR flash of two sectors behind
// config/flash_if.h, for the configuration store's tests: an erase sets
// every bit to 1, a program can only clear bits (a word asked to set a bit
// is refused and counted, a violation the store must never cause), and
// the power can be cut after any number of word operations: the word in
// progress is then left half done (a program: half of the bits it was to
// clear cleared, the lower ones; an erase: half of the bits it was to set
// set), and the flash does nothing more until the power comes back.
//
// An erase runs word by word from the sector's start, one word operation
// each; a program one per word. So a save's steps are its words, and a
// cut "after n operations" stops it at any of them or half-way into one.
#ifndef TESTS_FIRMWARE_SIM_FLASH_H
#define TESTS_FIRMWARE_SIM_FLASH_H

#include <cstdint>
#include <limits>
#include <vector>

extern "C" {
#include "config/flash_if.h"
}

class SimFlash {
public:
    explicit SimFlash(uint32_t sector_words)
        : words_(sector_words),
          mem_{std::vector<uint32_t>(sector_words, FLASH_IF_ERASED),
               std::vector<uint32_t>(sector_words, FLASH_IF_ERASED)}
    {
    }
    SimFlash(const SimFlash& o) : SimFlash(o.words_) { copy_from(o); }
    SimFlash& operator=(const SimFlash& o)
    {
        if (this != &o) copy_from(o);
        return *this;
    }

    // the interface the store is given (the bases point into this object)
    flash_if_t interface()
    {
        flash_if_t f{};
        f.ctx = this;
        f.sector_words = words_;
        f.base[0] = mem_[0].data();
        f.base[1] = mem_[1].data();
        f.erase = &SimFlash::erase_op;
        f.program = &SimFlash::program_op;
        f.error = &SimFlash::error_op;
        return f;
    }

    // the power goes after n more word operations, the next one half done
    void cut_after(uint64_t n, bool half_word)
    {
        budget_ = n;
        half_ = half_word;
    }
    void power_back()
    {
        budget_ = kNoCut;
        dead_ = false;
    }
    bool dead() const { return dead_; }

    // faults of a driver: refuse (the bridge enabled), or report success
    // while a word does not take (a stuck bit at word index, sector)
    bool refuse = false;
    int stuck_sector = -1;
    uint32_t stuck_word = 0, stuck_mask = 0;  // these bits stay 1 on a program, 0 on an erase

    std::vector<uint32_t>& sector(uint32_t s) { return mem_[s]; }
    const std::vector<uint32_t>& sector(uint32_t s) const { return mem_[s]; }
    uint32_t sector_words() const { return words_; }

    // counts
    uint64_t ops = 0;             // word operations done (a half one included)
    uint32_t erases[2] = {0, 0};  // erases started, per sector
    uint32_t nor_violations = 0;  // programs asking a bit to go from 0 to 1

private:
    static constexpr uint64_t kNoCut = std::numeric_limits<uint64_t>::max();

    void copy_from(const SimFlash& o)
    {
        mem_[0] = o.mem_[0];
        mem_[1] = o.mem_[1];
    }

    // one word operation: false once the power is gone (the word left
    // half done if the cut falls on it)
    bool step(uint32_t& word, uint32_t target)
    {
        if (dead_) return false;
        if (budget_ == 0) {
            dead_ = true;
            if (half_) word = half_way(word, target);
            ++ops;
            return false;
        }
        if (budget_ != kNoCut) --budget_;
        word = target;
        ++ops;
        return true;
    }
    // half of the bits that change, the lower ones
    static uint32_t half_way(uint32_t from, uint32_t to)
    {
        uint32_t diff = from ^ to;
        int n = __builtin_popcount(diff) / 2;
        uint32_t w = from;
        for (int b = 0; b < 32 && n > 0; ++b) {
            if (diff & (1u << b)) {
                w ^= 1u << b;
                --n;
            }
        }
        return w;
    }

    static flash_if_result_t erase_op(void* ctx, uint32_t s)
    {
        auto* f = static_cast<SimFlash*>(ctx);
        if (s > 1) return FLASH_IF_FAILED;
        if (f->refuse) {
            f->error_ = "refused: bridge enabled";
            return FLASH_IF_REFUSED;
        }
        if (f->dead_) return FLASH_IF_FAILED;
        f->erases[s]++;
        for (uint32_t i = 0; i < f->words_; ++i) {
            uint32_t target = FLASH_IF_ERASED;
            if (static_cast<int>(s) == f->stuck_sector && i == f->stuck_word) target &= ~f->stuck_mask;
            if (!f->step(f->mem_[s][i], target)) {
                f->error_ = "power cut during an erase";
                return FLASH_IF_FAILED;
            }
        }
        return FLASH_IF_OK;
    }

    static flash_if_result_t program_op(void* ctx, uint32_t s, uint32_t offset, const uint32_t* words, uint32_t n)
    {
        auto* f = static_cast<SimFlash*>(ctx);
        if (s > 1 || offset > f->words_ || n > f->words_ - offset) {
            f->error_ = "program outside the sector";
            return FLASH_IF_FAILED;
        }
        if (f->refuse) {
            f->error_ = "refused: bridge enabled";
            return FLASH_IF_REFUSED;
        }
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t& w = f->mem_[s][offset + i];
            if ((words[i] & ~w) != 0u) {  // a bit from 0 to 1: NOR cannot
                f->nor_violations++;
                f->error_ = "program of a word not erased";
                return FLASH_IF_FAILED;
            }
            uint32_t target = words[i];
            if (static_cast<int>(s) == f->stuck_sector && offset + i == f->stuck_word) target |= f->stuck_mask & w;
            if (!f->step(w, target)) {
                f->error_ = "power cut during a program";
                return FLASH_IF_FAILED;
            }
        }
        return FLASH_IF_OK;
    }

    static const char* error_op(void* ctx) { return static_cast<SimFlash*>(ctx)->error_; }

    uint32_t words_;
    std::vector<uint32_t> mem_[2];
    uint64_t budget_ = kNoCut;
    bool half_ = false;
    bool dead_ = false;
    const char* error_ = "";
};

#endif  // TESTS_FIRMWARE_SIM_FLASH_H
