// main.cpp - dtc-sil entry point; everything else is in the sil_run library (run.hpp).
#include <iostream>
#include <string>
#include <vector>

#include "controller_adapter.hpp"
#include "run.hpp"

int main(int argc, char** argv)
{
    sil::register_reference_controller(&sil::make_reference_controller);
    std::vector<std::string> args(argv, argv + argc);
    return sil::dtc_sil_main(args, std::cout, std::cerr);
}
