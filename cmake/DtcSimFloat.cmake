# dtc_sim_float(target): floating-point options of the host simulation's C++ (the plant, hal_host,
# the SIL run loop) that change no computed value, only how the compiler may lay the code out:
#   -fno-math-errno     the libm calls need not set errno (sqrt becomes the sqrtsd instruction
#                       without the branch and call kept for a negative argument's EDOM);
#   -fno-trapping-math  no floating-point operation is assumed to trap, so a conditional
#                       floating-point expression may be computed on both arms and selected.
# Measured together: the plant's right-hand side 415 -> 403 host instructions per evaluation.
# Neither permits reassociation, contraction or a different rounding (those are -ffast-math's
# -fassociative-math, -ffp-contract=fast, -freciprocal-math, ...): every double comes out bit for
# bit as before (docs/sil.md, section 7: metrics_baseline.py check exact). Nothing in the
# simulation reads errno or the floating-point exception flags. The firmware (fixed point) is
# not built with them.
function(dtc_sim_float target)
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-fno-math-errno -fno-trapping-math>)
endfunction()
