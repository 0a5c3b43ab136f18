// The fixture of the self-commissioning tests (test_identify.cpp, test_identify_im.cpp): a fresh
// directory per test, dtc-sil's command line in-process, `identify SCENARIO --out DIR/id` with
// --set overrides, and its two outputs.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_capture.hpp"

namespace sil_test {

class IdentifyFixture : public ::testing::Test {
protected:
    std::filesystem::path dir;
    void SetUp() override
    {
        dir = std::filesystem::temp_directory_path() /
              ("sil_identify_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }

    int cli(std::vector<std::string> args, std::string* err = nullptr) { return run_cli(std::move(args), nullptr, err); }
    int identify(const std::string& scenario, const std::vector<std::string>& sets, std::string* err = nullptr)
    {
        std::vector<std::string> a = {"identify", scenario, "--out", (dir / "id").string()};
        for (const auto& s : sets) {
            a.push_back("--set");
            a.push_back(s);
        }
        return cli(a, err);
    }
    static nlohmann::json json_of(const std::filesystem::path& p)
    {
        std::ifstream f(p);
        return nlohmann::json::parse(f);
    }
    nlohmann::json report() const { return json_of(dir / "id" / "identification.json"); }
    std::string toml() const
    {
        std::ifstream f(dir / "id" / "identified.toml");
        std::ostringstream s;
        s << f.rdbuf();
        return s.str();
    }
};

inline double id_of(const nlohmann::json& j, const char* q) { return j["quantities"][q]["identified"].get<double>(); }

} // namespace sil_test
