// hal_host_line.hpp - the serial line and the parameter storage medium of hal.h in the SIL.
//
// SerialLine: the DSP's UART (hal_serial_read / hal_serial_write) modelled in simulated time. Each
// direction carries at most baud / 10 octets per second (8N1: ten bits per octet), i.e.
// baud / 10 * ts octets per control period: advance_period() moves them, once per period, as the
// wire would. The DSP side has the SCI-A's two 16-octet FIFOs: hal_serial_write accepts what the
// transmit FIFO has room for; octets arriving into a full receive FIFO are lost and counted (an
// overrun, as on the DSP when the background loop does not read in time). The host side (a
// test, or a PtyLink to a pseudo-terminal) sends into an unbounded queue (the host's OS buffer)
// and receives what has crossed the wire.
//
// StoreMedium: words in RAM, optionally backed by a file (read at open, written through on every
// change), with the EEPROM's semantics (rewritten in place, erase does nothing) or the flash's
// (erase to 0xFFFF, a write only clears bits).
//
// PtyLink: a pseudo-terminal whose slave path is linked (symlink) at a path of the caller's
// choosing; pump() moves octets between it and a SerialLine's host side without blocking.
//
// The hal.h functions forward to the active SerialLine / StoreMedium (activate()); with none
// active the line is unplugged (reads nothing, accepts and drops every octet) and there is no
// medium (hal_store_words() = 0).
#ifndef HAL_HOST_LINE_HPP
#define HAL_HOST_LINE_HPP

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace hal_host {

class SerialLine {
public:
    static constexpr std::size_t kFifo = 16; // SCI-A FIFO depth (f2812-facts 9.1)

    SerialLine(double baud, double ts_s);
    ~SerialLine();
    SerialLine(const SerialLine&) = delete;
    SerialLine& operator=(const SerialLine&) = delete;

    void activate();   // hal_serial_* use this line
    void deactivate(); // (the destructor does it too)

    /// One control period of simulated time: up to baud/10*ts octets cross in each direction.
    void advance_period();

    // Host side.
    void host_send(const std::uint8_t* data, std::size_t n);
    std::vector<std::uint8_t> host_receive(); // everything that has crossed to the host

    // DSP side (hal.h semantics).
    std::uint16_t dsp_read(std::uint16_t* buf, std::uint16_t max);
    std::uint16_t dsp_write(const std::uint16_t* buf, std::uint16_t n);

    double octets_per_period() const { return octets_per_period_; }
    std::uint64_t rx_overruns() const { return rx_overruns_; }

private:
    double octets_per_period_;
    double credit_to_dsp_ = 0.0, credit_to_host_ = 0.0;
    std::deque<std::uint8_t> host_out_; // host -> wire, not yet sent
    std::deque<std::uint8_t> rx_fifo_;  // DSP receive FIFO
    std::deque<std::uint8_t> tx_fifo_;  // DSP transmit FIFO
    std::deque<std::uint8_t> host_in_;  // crossed to the host, not yet taken
    std::uint64_t rx_overruns_ = 0;
};

class StoreMedium {
public:
    enum class Kind { eeprom, flash };
    /// words: size (16-bit words); erase_words: erase unit (power of two dividing words).
    /// path: backing file ("" = RAM only); an existing file of the right size is loaded,
    /// otherwise the medium starts erased (0xFFFF). Throws std::runtime_error on a file error.
    StoreMedium(std::uint16_t words, std::uint16_t erase_words, Kind kind, const std::string& path = "");
    ~StoreMedium();
    StoreMedium(const StoreMedium&) = delete;
    StoreMedium& operator=(const StoreMedium&) = delete;

    void activate();
    void deactivate();

    std::uint16_t words() const { return static_cast<std::uint16_t>(w_.size()); }
    std::uint16_t erase_words() const { return erase_words_; }
    std::uint16_t read(std::uint16_t addr, std::uint16_t* buf, std::uint16_t n) const;
    std::uint16_t write(std::uint16_t addr, const std::uint16_t* buf, std::uint16_t n);
    std::uint16_t erase(std::uint16_t addr, std::uint16_t n);
    const std::vector<std::uint16_t>& contents() const { return w_; }

private:
    void flush() const;
    std::vector<std::uint16_t> w_;
    std::uint16_t erase_words_;
    Kind kind_;
    std::string path_;
};

class PtyLink {
public:
    /// Opens a pseudo-terminal (raw, 8 bit) and links its slave device at link_path (replacing a
    /// stale link). Throws std::runtime_error naming the step that failed.
    explicit PtyLink(const std::string& link_path);
    ~PtyLink(); // removes the link
    PtyLink(const PtyLink&) = delete;
    PtyLink& operator=(const PtyLink&) = delete;

    /// Moves what the client wrote into line's host side, and what crossed to the host out to
    /// the client. Never blocks.
    void pump(SerialLine& line);
    const std::string& slave_path() const { return slave_; }

private:
    int master_ = -1;
    int slave_keep_ = -1; // held open so the master never sees a hang-up between clients
    std::string slave_, link_;
    std::vector<std::uint8_t> pending_out_;
};

} // namespace hal_host

#endif // HAL_HOST_LINE_HPP
