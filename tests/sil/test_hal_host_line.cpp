// The SIL's serial line, pseudo-terminal and storage medium (hal/host/include/hal_host_line.hpp):
// octets cross at baud/10 per second of simulated time, the DSP side has the SCI-A's 16-octet
// FIFOs (overrun when not read), an idle wire banks no time, an unplugged line reads nothing;
// the medium keeps its words in a file across a restart, and the stored-parameter layer
// (firmware/comm/store.h) boots from it; a pseudo-terminal carries octets both ways.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include "hal.h"
#include "hal_host_line.hpp"

extern "C" {
#include "store.h"
}

using hal_host::PtyLink;
using hal_host::SerialLine;
using hal_host::StoreMedium;

namespace {
constexpr double kBaud = 115200.0;
constexpr double kTs = 50e-6;

std::filesystem::path temp_dir(const char* name)
{
    auto d = std::filesystem::temp_directory_path() / (std::string("dtc_line_") + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}
} // namespace

TEST(HalHostLine, OctetsCrossAtTheBaudRateInSimulatedTime)
{
    SerialLine line(kBaud, kTs);
    line.activate();
    EXPECT_NEAR(line.octets_per_period(), 0.576, 1e-12); // 115200 / 10 * 50 us
    std::vector<std::uint8_t> msg(1000);
    for (std::size_t i = 0; i < msg.size(); ++i) {
        msg[i] = static_cast<std::uint8_t>(i * 7u);
    }
    line.host_send(msg.data(), msg.size());
    // 1000 octets of 10 bits at 115200 baud: 86.8 ms = 1736.1 periods
    const double periods_needed = 1000.0 * 10.0 / kBaud / kTs;
    std::vector<std::uint16_t> got;
    int k = 0;
    for (; got.size() < msg.size() && k < 5000; ++k) {
        line.advance_period();
        std::uint16_t buf[32];
        const std::uint16_t n = hal_serial_read(buf, 32);
        got.insert(got.end(), buf, buf + n);
        // never ahead of the wire: at most floor(0.576 (k + 1)) octets after k + 1 periods
        ASSERT_LE(got.size(), static_cast<std::size_t>(std::floor(0.576 * (k + 1) + 1e-9)));
    }
    EXPECT_NEAR(k, periods_needed, 1.0);
    ASSERT_EQ(got.size(), msg.size());
    for (std::size_t i = 0; i < msg.size(); ++i) {
        ASSERT_EQ(got[i], msg[i]);
    }
    EXPECT_EQ(line.rx_overruns(), 0u);
}

TEST(HalHostLine, ReceiveFifoOverrunsWhenNotRead)
{
    SerialLine line(kBaud, kTs);
    line.activate();
    std::vector<std::uint8_t> msg(100, 0x55);
    line.host_send(msg.data(), msg.size());
    for (int k = 0; k < 1000; ++k) {
        line.advance_period();
    }
    std::uint16_t buf[64];
    EXPECT_EQ(hal_serial_read(buf, 64), SerialLine::kFifo); // the SCI-A FIFO depth
    EXPECT_EQ(line.rx_overruns(), 100u - SerialLine::kFifo);
}

TEST(HalHostLine, TransmitFifoAcceptsWhatItHasRoomFor)
{
    SerialLine line(kBaud, kTs);
    line.activate();
    std::vector<std::uint16_t> out(40);
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = static_cast<std::uint16_t>(0x100u + i); // bits 15:8 ignored
    }
    EXPECT_EQ(hal_serial_write(out.data(), 40), 16);
    EXPECT_EQ(hal_serial_write(out.data() + 16, 24), 0); // full, no wait
    std::vector<std::uint8_t> host;
    std::size_t sent = 16;
    for (int k = 0; k < 200; ++k) {
        line.advance_period();
        sent += hal_serial_write(out.data() + sent, static_cast<std::uint16_t>(out.size() - sent));
        const auto r = line.host_receive();
        host.insert(host.end(), r.begin(), r.end());
    }
    ASSERT_EQ(host.size(), 40u);
    for (std::size_t i = 0; i < host.size(); ++i) {
        EXPECT_EQ(host[i], static_cast<std::uint8_t>(i));
    }
}

TEST(HalHostLine, IdleWireBanksNoTime)
{
    SerialLine line(kBaud, kTs);
    line.activate();
    for (int k = 0; k < 10000; ++k) {
        line.advance_period();
    }
    const std::uint8_t msg[10] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    line.host_send(msg, 10);
    int k = 0;
    std::size_t got = 0;
    while (got < 10 && k < 100) {
        line.advance_period();
        std::uint16_t buf[16];
        got += hal_serial_read(buf, 16);
        ++k;
    }
    // 10 octets need 17.4 periods of line time; one banked octet at most
    EXPECT_GE(k, 16);
    EXPECT_LE(k, 18);
}

TEST(HalHostLine, UnpluggedLineAndNoMedium)
{
    std::uint16_t buf[4] = {1, 2, 3, 4};
    EXPECT_EQ(hal_serial_read(buf, 4), 0);
    EXPECT_EQ(hal_serial_write(buf, 4), 4); // dropped, as on a cable that is not there
    EXPECT_EQ(hal_store_words(), 0);
    EXPECT_EQ(hal_store_read(0, buf, 1), HAL_STORE_ERR_NONE);
}

TEST(HalHostLine, MediumSemanticsAndFile)
{
    const auto dir = temp_dir("medium");
    const std::string path = (dir / "params.bin").string();
    {
        StoreMedium m(256, 64, StoreMedium::Kind::flash, path);
        m.activate();
        EXPECT_EQ(hal_store_words(), 256);
        EXPECT_EQ(hal_store_erase_words(), 64);
        std::uint16_t w = 0x0F0F;
        EXPECT_EQ(hal_store_write(10, &w, 1), HAL_STORE_OK);
        w = 0xFF00; // flash: a write only clears bits
        EXPECT_EQ(hal_store_write(10, &w, 1), HAL_STORE_OK);
        EXPECT_EQ(hal_store_read(10, &w, 1), HAL_STORE_OK);
        EXPECT_EQ(w, 0x0F00);
        EXPECT_EQ(hal_store_erase(10, 64), HAL_STORE_ERR_RANGE); // not on an erase unit
        EXPECT_EQ(hal_store_read(250, &w, 7), HAL_STORE_ERR_RANGE);
    }
    {
        StoreMedium m(256, 64, StoreMedium::Kind::flash, path); // a restart: the file holds it
        std::uint16_t w = 0;
        EXPECT_EQ(m.read(10, &w, 1), HAL_STORE_OK);
        EXPECT_EQ(w, 0x0F00);
        EXPECT_EQ(m.erase(0, 64), HAL_STORE_OK);
        EXPECT_EQ(m.read(10, &w, 1), HAL_STORE_OK);
        EXPECT_EQ(w, 0xFFFF);
    }
    {
        StoreMedium m(128, 64, StoreMedium::Kind::eeprom, (dir / "e.bin").string());
        std::uint16_t w = 0x1234;
        EXPECT_EQ(m.write(5, &w, 1), HAL_STORE_OK);
        w = 0xABCD; // EEPROM: rewritten in place
        EXPECT_EQ(m.write(5, &w, 1), HAL_STORE_OK);
        EXPECT_EQ(m.erase(0, 128), HAL_STORE_OK); // does nothing
        EXPECT_EQ(m.read(5, &w, 1), HAL_STORE_OK);
        EXPECT_EQ(w, 0xABCD);
    }
    EXPECT_THROW(StoreMedium(512, 64, StoreMedium::Kind::flash, path), std::runtime_error); // wrong size
    std::filesystem::remove_all(dir);
}

// The stored-parameter layer on the SIL's file medium: a save survives a restart of the process
// (a new medium object on the same file) and is what the next boot loads.
TEST(HalHostLine, StoredParametersSurviveARestart)
{
    const auto dir = temp_dir("store");
    const std::string path = (dir / "params.bin").string();
    const std::uint16_t defaults[4] = {1, 2, 3, 4};
    const std::uint16_t changed[4] = {10, 20, 30, 40};
    // One power-up on the medium kept in the file: the boot's status and values, then a save of
    // `save` where it is not null (the medium is written back to the file when m goes).
    const auto power_up = [&](int want_rc, const std::uint16_t* want, const std::uint16_t* save) {
        StoreMedium m(1024, 32, StoreMedium::Kind::eeprom, path);
        m.activate();
        store_t st;
        std::uint16_t d[4];
        EXPECT_EQ(store_boot(&st, 7, d, defaults, 4), want_rc);
        EXPECT_EQ(std::vector<std::uint16_t>(d, d + 4), std::vector<std::uint16_t>(want, want + 4));
        if (save != nullptr) {
            EXPECT_EQ(store_save(&st, 0, 7, save, 4), STORE_OK);
        }
    };
    power_up(STORE_DEFAULTS, defaults, changed);
    power_up(STORE_OK, changed, nullptr);
    std::filesystem::remove_all(dir);
}

TEST(HalHostLine, PseudoTerminalCarriesOctetsBothWays)
{
    const auto dir = temp_dir("pty");
    const std::string link = (dir / "drive").string();
    SerialLine line(kBaud, kTs);
    line.activate();
    PtyLink pty(link);
    ASSERT_TRUE(std::filesystem::is_symlink(link));
    const int fd = ::open(link.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    ASSERT_GE(fd, 0);
    termios t{};
    ASSERT_EQ(::tcgetattr(fd, &t), 0);
    ::cfmakeraw(&t);
    ASSERT_EQ(::tcsetattr(fd, TCSANOW, &t), 0);
    const std::uint8_t hello[6] = {0xA5, 0x00, 0x01, 0x07, 0x0D, 0x0A}; // raw: CR/LF pass unchanged
    ASSERT_EQ(::write(fd, hello, 6), 6);
    std::vector<std::uint16_t> got;
    for (int k = 0; k < 100 && got.size() < 6; ++k) {
        pty.pump(line);
        line.advance_period();
        std::uint16_t buf[16];
        const std::uint16_t n = hal_serial_read(buf, 16);
        got.insert(got.end(), buf, buf + n);
    }
    ASSERT_EQ(got.size(), 6u);
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(got[i], hello[i]);
    }
    const std::uint16_t reply[3] = {0xA5, 0x11, 0xFF};
    EXPECT_EQ(hal_serial_write(reply, 3), 3);
    std::vector<std::uint8_t> back;
    for (int k = 0; k < 100 && back.size() < 3; ++k) {
        line.advance_period();
        pty.pump(line);
        std::uint8_t b[16];
        const ssize_t r = ::read(fd, b, sizeof b);
        if (r > 0) {
            back.insert(back.end(), b, b + r);
        }
    }
    ASSERT_EQ(back.size(), 3u);
    EXPECT_EQ(back[0], 0xA5);
    EXPECT_EQ(back[1], 0x11);
    EXPECT_EQ(back[2], 0xFF);
    ::close(fd);
    std::filesystem::remove_all(dir);
}
