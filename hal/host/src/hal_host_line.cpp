// hal_host_line.cpp - serial line, storage medium and pseudo-terminal of the SIL (hal_host_line.hpp).
#include "hal_host_line.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include "hal.h"

namespace hal_host {

namespace {
SerialLine* g_line = nullptr;
StoreMedium* g_medium = nullptr;
} // namespace

// ---- SerialLine ------------------------------------------------------------------------------
SerialLine::SerialLine(double baud, double ts_s) : octets_per_period_(baud / 10.0 * ts_s)
{
    if (!(baud > 0.0) || !(ts_s > 0.0)) {
        throw std::runtime_error("SerialLine: baud and ts_s must be positive");
    }
}

SerialLine::~SerialLine() { deactivate(); }
void SerialLine::activate() { g_line = this; }
void SerialLine::deactivate()
{
    if (g_line == this) {
        g_line = nullptr;
    }
}

void SerialLine::advance_period()
{
    // A direction with nothing to send banks at most one octet of line time: an idle wire does not
    // store up transmissions.
    credit_to_dsp_ += octets_per_period_;
    while (credit_to_dsp_ >= 1.0 && !host_out_.empty()) {
        if (rx_fifo_.size() < kFifo) {
            rx_fifo_.push_back(host_out_.front());
        } else {
            ++rx_overruns_; // arrived with the FIFO full: lost
        }
        host_out_.pop_front();
        credit_to_dsp_ -= 1.0;
    }
    if (host_out_.empty() && credit_to_dsp_ > 1.0) {
        credit_to_dsp_ = 1.0;
    }
    credit_to_host_ += octets_per_period_;
    while (credit_to_host_ >= 1.0 && !tx_fifo_.empty()) {
        host_in_.push_back(tx_fifo_.front());
        tx_fifo_.pop_front();
        credit_to_host_ -= 1.0;
    }
    if (tx_fifo_.empty() && credit_to_host_ > 1.0) {
        credit_to_host_ = 1.0;
    }
}

void SerialLine::host_send(const std::uint8_t* data, std::size_t n) { host_out_.insert(host_out_.end(), data, data + n); }

std::vector<std::uint8_t> SerialLine::host_receive()
{
    std::vector<std::uint8_t> out(host_in_.begin(), host_in_.end());
    host_in_.clear();
    return out;
}

std::uint16_t SerialLine::dsp_read(std::uint16_t* buf, std::uint16_t max)
{
    std::uint16_t n = 0;
    while (n < max && !rx_fifo_.empty()) {
        buf[n++] = rx_fifo_.front();
        rx_fifo_.pop_front();
    }
    return n;
}

std::uint16_t SerialLine::dsp_write(const std::uint16_t* buf, std::uint16_t n)
{
    std::uint16_t k = 0;
    while (k < n && tx_fifo_.size() < kFifo) {
        tx_fifo_.push_back(static_cast<std::uint8_t>(buf[k] & 0xFFu));
        ++k;
    }
    return k;
}

// ---- StoreMedium -----------------------------------------------------------------------------
StoreMedium::StoreMedium(std::uint16_t words, std::uint16_t erase_words, Kind kind, const std::string& path)
    : w_(words, 0xFFFFu), erase_words_(erase_words), kind_(kind), path_(path)
{
    if (erase_words == 0 || (erase_words & (erase_words - 1u)) != 0 || words % erase_words != 0) {
        throw std::runtime_error("StoreMedium: erase_words must be a power of two dividing words");
    }
    if (!path_.empty()) {
        std::ifstream f(path_, std::ios::binary);
        if (f) {
            std::vector<char> raw((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
            if (raw.size() == 2u * w_.size()) {
                for (std::size_t i = 0; i < w_.size(); ++i) { // little-endian words
                    w_[i] = static_cast<std::uint16_t>(static_cast<unsigned char>(raw[2 * i]) |
                                                       (static_cast<unsigned char>(raw[2 * i + 1]) << 8));
                }
            } else {
                throw std::runtime_error("StoreMedium: " + path_ + ": size " + std::to_string(raw.size()) +
                                         " octets, expected " + std::to_string(2u * w_.size()));
            }
        } else {
            flush();
        }
    }
}

StoreMedium::~StoreMedium() { deactivate(); }
void StoreMedium::activate() { g_medium = this; }
void StoreMedium::deactivate()
{
    if (g_medium == this) {
        g_medium = nullptr;
    }
}

void StoreMedium::flush() const
{
    if (path_.empty()) {
        return;
    }
    std::ofstream f(path_, std::ios::binary | std::ios::trunc);
    for (std::uint16_t v : w_) {
        const char b[2] = {static_cast<char>(v & 0xFFu), static_cast<char>(v >> 8)};
        f.write(b, 2);
    }
    if (!f) {
        throw std::runtime_error("StoreMedium: cannot write " + path_);
    }
}

std::uint16_t StoreMedium::read(std::uint16_t addr, std::uint16_t* buf, std::uint16_t n) const
{
    if (static_cast<std::size_t>(addr) + n > w_.size()) {
        return HAL_STORE_ERR_RANGE;
    }
    for (std::uint16_t i = 0; i < n; ++i) {
        buf[i] = w_[addr + i];
    }
    return HAL_STORE_OK;
}

std::uint16_t StoreMedium::write(std::uint16_t addr, const std::uint16_t* buf, std::uint16_t n)
{
    if (static_cast<std::size_t>(addr) + n > w_.size()) {
        return HAL_STORE_ERR_RANGE;
    }
    for (std::uint16_t i = 0; i < n; ++i) {
        w_[addr + i] = kind_ == Kind::flash ? static_cast<std::uint16_t>(w_[addr + i] & buf[i]) : buf[i];
    }
    flush();
    return HAL_STORE_OK;
}

std::uint16_t StoreMedium::erase(std::uint16_t addr, std::uint16_t n)
{
    if (static_cast<std::size_t>(addr) + n > w_.size() || addr % erase_words_ != 0 || n % erase_words_ != 0) {
        return HAL_STORE_ERR_RANGE;
    }
    if (kind_ == Kind::flash) {
        for (std::uint16_t i = 0; i < n; ++i) {
            w_[addr + i] = 0xFFFFu;
        }
        flush();
    }
    return HAL_STORE_OK;
}

// ---- PtyLink ---------------------------------------------------------------------------------
PtyLink::PtyLink(const std::string& link_path) : link_(link_path)
{
    auto fail = [&](const char* step) {
        const std::string msg = std::string("PtyLink: ") + step + ": " + std::strerror(errno);
        if (master_ >= 0) {
            ::close(master_);
        }
        if (slave_keep_ >= 0) {
            ::close(slave_keep_);
        }
        throw std::runtime_error(msg);
    };
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (master_ < 0) {
        fail("posix_openpt");
    }
    if (::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
        fail("grantpt/unlockpt");
    }
    const char* name = ::ptsname(master_);
    if (name == nullptr) {
        fail("ptsname");
    }
    slave_ = name;
    slave_keep_ = ::open(slave_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (slave_keep_ < 0) {
        fail("open slave");
    }
    termios t{};
    if (::tcgetattr(slave_keep_, &t) != 0) {
        fail("tcgetattr");
    }
    ::cfmakeraw(&t);
    if (::tcsetattr(slave_keep_, TCSANOW, &t) != 0) {
        fail("tcsetattr");
    }
    ::unlink(link_.c_str()); // a stale link from an earlier run
    if (::symlink(slave_.c_str(), link_.c_str()) != 0) {
        fail(("symlink " + link_).c_str());
    }
}

PtyLink::~PtyLink()
{
    ::unlink(link_.c_str());
    if (slave_keep_ >= 0) {
        ::close(slave_keep_);
    }
    if (master_ >= 0) {
        ::close(master_);
    }
}

void PtyLink::pump(SerialLine& line)
{
    std::uint8_t buf[256];
    for (;;) {
        const ssize_t r = ::read(master_, buf, sizeof buf);
        if (r <= 0) {
            break; // EAGAIN: nothing more now
        }
        line.host_send(buf, static_cast<std::size_t>(r));
    }
    const std::vector<std::uint8_t> out = line.host_receive();
    pending_out_.insert(pending_out_.end(), out.begin(), out.end());
    while (!pending_out_.empty()) {
        const ssize_t w = ::write(master_, pending_out_.data(), pending_out_.size());
        if (w <= 0) {
            break; // the client is not reading: keep the rest for the next pump
        }
        pending_out_.erase(pending_out_.begin(), pending_out_.begin() + w);
    }
}

} // namespace hal_host

// ---- hal.h -------------------------------------------------------------------------------------
extern "C" {

uint16_t hal_serial_read(uint16_t* buf, uint16_t max)
{
    return hal_host::g_line != nullptr ? hal_host::g_line->dsp_read(buf, max) : 0u;
}

uint16_t hal_serial_write(const uint16_t* buf, uint16_t n)
{
    return hal_host::g_line != nullptr ? hal_host::g_line->dsp_write(buf, n) : n; // unplugged: dropped
}

uint16_t hal_store_words(void) { return hal_host::g_medium != nullptr ? hal_host::g_medium->words() : 0u; }
uint16_t hal_store_erase_words(void)
{
    return hal_host::g_medium != nullptr ? hal_host::g_medium->erase_words() : 1u;
}
uint16_t hal_store_read(uint16_t addr, uint16_t* buf, uint16_t n)
{
    return hal_host::g_medium != nullptr ? hal_host::g_medium->read(addr, buf, n) : static_cast<uint16_t>(HAL_STORE_ERR_NONE);
}
uint16_t hal_store_write(uint16_t addr, const uint16_t* buf, uint16_t n)
{
    return hal_host::g_medium != nullptr ? hal_host::g_medium->write(addr, buf, n) : static_cast<uint16_t>(HAL_STORE_ERR_NONE);
}
uint16_t hal_store_erase(uint16_t addr, uint16_t n)
{
    return hal_host::g_medium != nullptr ? hal_host::g_medium->erase(addr, n) : static_cast<uint16_t>(HAL_STORE_ERR_NONE);
}

} // extern "C"
