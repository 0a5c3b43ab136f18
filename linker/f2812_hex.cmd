/*
 * f2812_hex.cmd - hex2000 options for third-party flash programmers: Intel hex of the flash
 * image (16-bit words). CCS/UniFlash/SDFlash program the .out directly and do not need it.
 * Options: fact sheet 6.5 (SPRU513 ✔). Only the flash range is emitted; RAM-run sections are in
 * the image at their LOAD addresses. Sparse output (no --image): erased words stay erased,
 * including the CSM password, which must never become all zeros.
 */
--intel
--memwidth=16
--romwidth=16

ROMS
{
    PAGE 0:
        FLASH : origin = 0x3D8000, length = 0x020000
}
