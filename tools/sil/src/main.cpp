// main.cpp - dtc-sil entry point; everything else is in the sil_run library (run.hpp).
#include <iostream>
#include <string>
#include <vector>

#include "run.hpp"

int main(int argc, char** argv)
{
    std::vector<std::string> args(argv, argv + argc);
    return sil::dtc_sil_main(args, std::cout, std::cerr);
}
