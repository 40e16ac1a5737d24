#include "reports/paper_table.hpp"

#include <gtest/gtest.h>

namespace statebench::reports {
namespace {

nlohmann::json Metrics(double x, double y, double yaw, double v_lon, double ape, double nees) {
  return {{"compared", 2400},
          {"rmse", {{"x_m", x}, {"y_m", y}, {"yaw_rad", yaw}, {"v_longitudinal_mps", v_lon}}},
          {"ape", {{"translation_m", {{"rmse", ape}}}}},
          {"nees", {{"pose_6dof_mean", nees}}},
          {"outages", nlohmann::json::array()},
          {"during_outages", nlohmann::json::array()}};
}

nlohmann::json RunJson(const std::string& scenario, const nlohmann::json& estimators) {
  return {{"scenario", scenario}, {"simulated_s", 240.0},    {"distance_m", 1134.2},
          {"wall_time_s", 80.0},  {"real_time_factor", 3.0}, {"estimators", estimators}};
}

// Setup 2 with the factor graph and the EKF; setup 3 with a GNSS outage seen by the factor graph
// only; setup 1 (no paper numbers); a failed run.
std::vector<ScenarioRun> SuiteRuns() {
  nlohmann::json outage_fg = Metrics(0.1, 0.2, 0.01, 0.05, 0.3, 5.5);
  outage_fg["outages"] = {{{"distance_m", 350.4},
                           {"error_end_x_m", -1.234},
                           {"error_end_y_m", 0.5},
                           {"drift_percent_of_distance", 0.38}}};
  outage_fg["during_outages"] = {
      {{"compared", 600},
       {"rmse", {{"x_m", 0.7}, {"y_m", 0.35}, {"yaw_rad", 0.012}, {"v_longitudinal_mps", 0.08}}}}};
  return {
      {"setup2_quadricycle",
       RunJson("setup2_quadricycle",
               {{{"label", "factor_graph"},
                 {"type", "factor_graph"},
                 {"metrics", Metrics(0.46, 0.507, 0.0273, 0.57, 0.833, 7.34)}},
                {{"label", "ekf"},
                 {"type", "ekf"},
                 {"metrics", Metrics(0.293, 0.272, 0.0108, 0.066, 0.542, 3.81)}}}),
       ""},
      {"setup3_shuttle",
       RunJson("setup3_shuttle",
               {{{"label", "factor_graph"}, {"type", "factor_graph"}, {"metrics", outage_fg}},
                {{"label", "ekf"},
                 {"type", "ekf"},
                 {"metrics", Metrics(0.2, 0.3, 0.02, 0.1, 0.4, 4.0)}}}),
       ""},
      {"setup1_quadricycle",
       RunJson("setup1_quadricycle", {{{"label", "fg_w0.5"},
                                       {"type", "factor_graph"},
                                       {"metrics", Metrics(0.01, 0.02, 0.003, 0.04, 0.025, 6.1)}}}),
       ""},
      {"setup3_shuttle_rtk", std::nullopt, "exit code 2"},
  };
}

TEST(PaperTable, SetsTheSetup2RowsOfTableIBesideOurs) {
  const PaperTable table = BuildPaperTable(SuiteRuns());
  ASSERT_EQ(table.sections.size(), 4u);
  const TableSection& s2 = table.sections[0];
  EXPECT_EQ(s2.scenario, "setup2_quadricycle");
  EXPECT_EQ(s2.labels, (std::vector<std::string>{"factor_graph", "ekf"}));
  ASSERT_EQ(s2.rows.size(), 6u);  // no outage rows without an outage
  EXPECT_EQ(s2.rows[0].metric->id, "rmse_x");
  EXPECT_DOUBLE_EQ(*s2.rows[0].paper_fg, 0.40);
  EXPECT_DOUBLE_EQ(*s2.rows[0].paper_ekf, 0.30);
  EXPECT_DOUBLE_EQ(*s2.rows[0].ours[0], 0.46);
  EXPECT_DOUBLE_EQ(*s2.rows[0].ours[1], 0.293);
  EXPECT_DOUBLE_EQ(*s2.rows[3].paper_ekf, 0.147);
  EXPECT_EQ(s2.rows[5].metric->id, "nees");
  EXPECT_FALSE(s2.rows[5].paper_fg.has_value());

  const std::string md = ToMarkdown(table);
  EXPECT_NE(md.find("| metric | paper FG | paper EKF | factor_graph | ekf |\n"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| RMSE X [m] | 0.40 | 0.30 | 0.460 | 0.293 |\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| RMSE Y [m] | 0.38 | 0.39 | 0.507 | 0.272 |\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| RMSE yaw [rad] | 0.04 | 0.06 | 0.0273 | 0.0108 |\n"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| RMSE longitudinal velocity [m/s] | 0.16 | 0.147 | 0.570 | 0.066 |\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| pose NEES, mean (6 dof: ideal 6) | - | - | 7.34 | 3.81 |\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("240 s simulated, 1134 m driven, wall time 80.0 s (3.00x real time)"),
            std::string::npos)
      << md;
}

TEST(PaperTable, OutageRowsCompareTheSetup3Text) {
  const PaperTable table = BuildPaperTable(SuiteRuns());
  const TableSection& s3 = table.sections[1];
  ASSERT_EQ(s3.rows.size(), 14u);
  const TableRow& err_x = s3.rows[11];
  EXPECT_EQ(err_x.metric->id, "outage_error_x");
  EXPECT_DOUBLE_EQ(*err_x.paper_fg, 0.2);
  EXPECT_FALSE(err_x.paper_ekf.has_value());
  EXPECT_DOUBLE_EQ(*err_x.ours[0], 1.234);  // magnitude of the signed error
  EXPECT_FALSE(err_x.ours[1].has_value());  // the EKF run has no outage entry
  const std::string md = ToMarkdown(table);
  EXPECT_NE(md.find("| GNSS outage: RMSE X [m] | 0.056 | - | 0.700 | - |\n"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| GNSS outage: distance driven [m] | 77 | - | 350 | - |\n"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| GNSS outage: position error at its end per distance [%] | 0.82 | - | "
                    "0.38 | - |\n"),
            std::string::npos)
      << md;
}

TEST(PaperTable, ScenariosWithoutPaperNumbersAndFailedRuns) {
  const PaperTable table = BuildPaperTable(SuiteRuns());
  const TableSection& s1 = table.sections[2];
  ASSERT_EQ(s1.rows.size(), 6u);
  for (const TableRow& row : s1.rows) {
    EXPECT_FALSE(row.paper_fg || row.paper_ekf) << row.metric->id;
  }
  const TableSection& failed = table.sections[3];
  EXPECT_EQ(failed.failure, "exit code 2");
  EXPECT_TRUE(failed.rows.empty());
  // A failed setup-2 run still shows the paper's rows, with no columns of ours.
  const PaperTable only_paper = BuildPaperTable({{"setup2_quadricycle", std::nullopt, "killed"}});
  ASSERT_EQ(only_paper.sections[0].rows.size(), 4u);
  EXPECT_TRUE(only_paper.sections[0].rows[0].ours.empty());
  const std::string md = ToMarkdown(only_paper);
  EXPECT_NE(md.find("**Run failed**: killed"), std::string::npos) << md;
  EXPECT_NE(md.find("| RMSE X [m] | 0.40 | 0.30 |\n"), std::string::npos) << md;
}

TEST(PaperTable, NoComparedEstimatesMeansNoValue) {
  // An estimator that never initialised: its zeros are not errors of zero.
  nlohmann::json never = Metrics(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  never["compared"] = 0;
  nlohmann::json outage = Metrics(0.1, 0.2, 0.01, 0.05, 0.3, 5.5);
  outage["outages"] = {{{"distance_m", 0.0},
                        {"error_end_x_m", 0.0},
                        {"error_end_y_m", 0.0},
                        {"drift_percent_of_distance", 0.0}}};
  outage["during_outages"] = {{{"compared", 0}, {"rmse", {{"x_m", 0.0}}}}};
  const PaperTable table = BuildPaperTable(
      {{"setup2_quadricycle",
        RunJson("setup2_quadricycle",
                {{{"label", "factor_graph"}, {"type", "factor_graph"}, {"metrics", never}},
                 {{"label", "late"}, {"type", "factor_graph"}, {"metrics", outage}}}),
        ""}});
  const TableSection& s = table.sections[0];
  ASSERT_EQ(s.rows.size(), 6u);  // outage rows only had estimates-free entries
  EXPECT_FALSE(s.rows[0].ours[0].has_value());
  EXPECT_DOUBLE_EQ(*s.rows[0].ours[1], 0.1);
  EXPECT_NE(ToMarkdown(table).find("| RMSE X [m] | 0.40 | 0.30 | - | 0.100 |\n"),
            std::string::npos);
}

TEST(PaperTable, JsonCarriesPaperSourcesAndOurValues) {
  const nlohmann::json j = ToJson(BuildPaperTable(SuiteRuns()));
  const nlohmann::json& s2 = j.at("sections").at(0);
  EXPECT_EQ(s2.at("scenario"), "setup2_quadricycle");
  EXPECT_EQ(s2.at("columns").at(1).at("type"), "ekf");
  const nlohmann::json& rmse_x = s2.at("rows").at(0);
  EXPECT_EQ(rmse_x.at("id"), "rmse_x");
  EXPECT_DOUBLE_EQ(rmse_x.at("paper").at("factor_graph").at("value").get<double>(), 0.40);
  EXPECT_EQ(rmse_x.at("paper").at("ekf").at("source"), "Table I");
  EXPECT_DOUBLE_EQ(rmse_x.at("ours").at("ekf").get<double>(), 0.293);
  const nlohmann::json& s3 = j.at("sections").at(1);
  EXPECT_TRUE(s3.at("rows").at(6).at("ours").at("ekf").is_null());
  EXPECT_EQ(j.at("sections").at(3).at("failure"), "exit code 2");
}

}  // namespace
}  // namespace statebench::reports
