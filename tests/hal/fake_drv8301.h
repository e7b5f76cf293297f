// A fake SPI master's registers (spi_regs_t) with DRV8301s behind them
// (hal/backends/stm32f405/drv8301.h), for the host tests: poll() plays the
// hardware from another thread. Each chip answers as the datasheet
// (SLOS719) says, one frame late: the word shifted out during frame N is
// the answer to the command of frame N-1 (bit 15 the frame error, bits
// 14:11 the address, 10:0 the register); a read command's answer carries
// the register, a write stores its 11 data bits in control register 1 or 2.
//
// The SPI's flags as the driver sees them on the chip: TXE set while the
// fake is ready for a word; a word written to DR (the fake keeps a tag in
// DR's upper half, which a 16-bit write clears: that is how it sees the
// write) is taken by the chip selected at that moment (the last chip select
// written low to the port's BSRR, read and cleared atomically); then the
// answer in DR and RXNE (TXE clear until the driver has moved its chip
// select again, so that a stale RXNE is never seen: the real RXNE clears
// when DR is read, which a fake in RAM cannot see). Modes make one flag
// never come: TXE (no word taken), RXNE (a word taken, no answer), BSY
// (stuck busy after the answer).
#ifndef TESTS_HAL_FAKE_DRV8301_H
#define TESTS_HAL_FAKE_DRV8301_H

#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

extern "C" {
#include "drv8301.h"
#include "stm32f405_regs.h"
}

class FakeDrv8301 {
public:
    enum class Mode { kOk, kNoTxe, kNoRxne, kBusyStuck };
    struct Frame {
        int chip;       // 0, 1, or -1: no chip selected
        uint16_t word;  // what the master shifted out
    };

    FakeDrv8301(spi_regs_t* spi, gpio_regs_t* cs_port, uint32_t cs0, uint32_t cs1)
        : spi_(spi), port_(cs_port), cs_{cs0, cs1}
    {
        reset();
    }

    // the SPI idle and both chips at their reset values (after a memset of
    // the registers the fake works on)
    void reset()
    {
        std::lock_guard<std::mutex> lock(m_);
        for (auto& r : regs_) {
            for (auto& v : r) v = 0u;
        }
        answer_[0] = answer_[1] = 0u;
        selected_ = -1;
        state_ = State::kReady;
        frames_.clear();
        spi_->DR = kTag;
        spi_->SR = 0u;
    }

    std::atomic<Mode> mode{Mode::kOk};
    // a chip (0, 1) that drops its writes to the control register at
    // address drop_writes_addr (-1: none): its read-back differs
    std::atomic<int> drop_writes_chip{-1};
    std::atomic<int> drop_writes_addr{-1};

    void set_reg(int chip, uint32_t addr, uint16_t v)
    {
        std::lock_guard<std::mutex> lock(m_);
        regs_[chip][addr & 3u] = static_cast<uint16_t>(v & DRV8301_DATA_MASK);
    }
    uint16_t reg(int chip, uint32_t addr) const
    {
        std::lock_guard<std::mutex> lock(m_);
        return regs_[chip][addr & 3u];
    }
    std::vector<Frame> frames() const
    {
        std::lock_guard<std::mutex> lock(m_);
        return frames_;
    }
    std::vector<uint16_t> words_to(int chip) const
    {
        std::vector<uint16_t> w;
        for (const auto& f : frames()) {
            if (f.chip == chip) w.push_back(f.word);
        }
        return w;
    }
    // the chip selected now (the last chip select the fake saw written low), -1 none
    int selected() const
    {
        std::lock_guard<std::mutex> lock(m_);
        return selected_;
    }

    // One pass of the hardware: call it repeatedly (a thread).
    void poll()
    {
        std::lock_guard<std::mutex> lock(m_);
        take_chip_selects();
        const Mode md = mode.load();
        if (state_ == State::kReady) {
            spi_->SR = (md == Mode::kNoTxe) ? 0u : SPI_SR_TXE;
            const uint32_t dr = spi_->DR;
            if (md == Mode::kNoTxe || (dr >> 16) != 0u) return;
            // a word: the chip select written before it is visible now
            take_chip_selects();
            const uint16_t word = static_cast<uint16_t>(dr & 0xFFFFu);
            frames_.push_back({selected_, word});
            const uint16_t out = (selected_ >= 0) ? shift(selected_, word) : 0xFFFFu;
            if (md == Mode::kNoRxne) {
                spi_->DR = kTag;
                spi_->SR = 0u;
            } else {
                spi_->DR = kTag | out;
                spi_->SR = SPI_SR_RXNE | (md == Mode::kBusyStuck ? SPI_SR_BSY : 0u);
            }
            state_ = State::kAnswered;
        }
    }

private:
    enum class State { kReady, kAnswered };
    static constexpr uint32_t kTag = 0xA5A50000u;

    // the port's BSRR, read and cleared in one atomic step (the master's
    // plain store is never lost between a read and a clear); a chip
    // select moved ends the answered frame
    void take_chip_selects()
    {
        auto* bsrr = const_cast<uint32_t*>(&port_->BSRR);
        const uint32_t mask =
            (1u << cs_[0]) | (1u << cs_[1]) | (1u << (cs_[0] + 16u)) | (1u << (cs_[1] + 16u));
        if ((__atomic_load_n(bsrr, __ATOMIC_SEQ_CST) & mask) == 0u) return;
        const uint32_t w = __atomic_exchange_n(bsrr, 0u, __ATOMIC_SEQ_CST);
        if ((w & mask) == 0u) return;
        // the last write wins: a reset bit (low) selects, a set bit (high) deselects
        if ((w & (1u << (cs_[0] + 16u))) != 0u) {
            selected_ = 0;
        } else if ((w & (1u << (cs_[1] + 16u))) != 0u) {
            selected_ = 1;
        } else {
            selected_ = -1;
        }
        if (state_ == State::kAnswered) {
            state_ = State::kReady;
            spi_->DR = kTag;
        }
    }

    // the chip's answer to the previous word; this word's taken
    uint16_t shift(int chip, uint16_t word)
    {
        const uint16_t out = answer_[chip];
        const uint32_t addr = DRV8301_FRAME_ADDR_OF(word);
        if (addr > DRV8301_REG_CTRL2) {
            answer_[chip] = DRV8301_FRAME_READ;  // frame error
            return out;
        }
        if ((word & DRV8301_FRAME_READ) == 0u && addr >= DRV8301_REG_CTRL1 &&
            !(drop_writes_chip.load() == chip && drop_writes_addr.load() == static_cast<int>(addr))) {
            regs_[chip][addr] = static_cast<uint16_t>(word & DRV8301_DATA_MASK);
        }
        answer_[chip] = static_cast<uint16_t>(DRV8301_FRAME_ADDR(addr) | regs_[chip][addr]);
        return out;
    }

    spi_regs_t* spi_;
    gpio_regs_t* port_;
    uint32_t cs_[2];
    mutable std::mutex m_;
    uint16_t regs_[2][4]{};
    uint16_t answer_[2]{};
    int selected_ = -1;
    State state_ = State::kReady;
    std::vector<Frame> frames_;
};

#endif  // TESTS_HAL_FAKE_DRV8301_H
