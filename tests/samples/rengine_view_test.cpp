// rengine-view's trajectory reader, without a display: the rows of rengine-sim's CSV
// become each body's samples, posed between rows for drawing; rows that are not the
// format's are refused naming their line.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "Trajectory.h"

using REngine::RQuat;
using REngine::RVec3;
using rengineview::Trajectory;
using rengineview::TrajectoryError;

namespace {
const std::string kHeader = "step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";

Trajectory Read(const std::string& rows) {
  std::istringstream in(kHeader + rows);
  return Trajectory::Read(in, "t.csv");
}

std::string ErrorOf(const std::string& text) {
  std::istringstream in(text);
  try {
    Trajectory::Read(in, "t.csv");
  } catch (const TrajectoryError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// A box moving along x and turning about z, and a ball added at step 1 (rows from then on):
// halfway between rows the box is halfway along and half turned; the ball is not there
// before its first row.
TEST(RengineView, TrajectoryRowsArePosedBetweenForDrawing) {
  const double c = std::cos(0.25), s = std::sin(0.25);  // half of 0.5 rad about z
  const Trajectory t = Read(
      "0,0,box,1000000,0,0,1,0,0,0,0,0,0,0,0,0\n"
      "1,0.5,box,1000001,0,0," +
      std::to_string(c) + ",0,0," + std::to_string(s) +
      ",0,0,0,0,0,0\n"
      "1,0.5,ball,5,5,5,1,0,0,0,0,0,0,0,0,0\n"
      "2,1,box,1000002,0,0,1,0,0,0,0,0,0,0,0,0\n"
      "2,1,ball,6,5,5,1,0,0,0,0,0,0,0,0,0\n");
  ASSERT_EQ(t.Bodies().size(), 2u);
  EXPECT_EQ(t.Bodies()[0], "box");
  EXPECT_EQ(t.Rows(), 5u);
  EXPECT_EQ(t.StartTime(), 0);
  EXPECT_EQ(t.EndTime(), 1);
  RVec3 p;
  RQuat q;
  ASSERT_TRUE(t.PoseAt(0, 0.25, p, q));
  EXPECT_NEAR(p.x(), 1000000.5, 1e-9);
  EXPECT_NEAR(q.angularDistance(RQuat(Eigen::AngleAxis<double>(0.25, RVec3::UnitZ()))), 0, 1e-6);
  EXPECT_FALSE(t.PoseAt(1, 0.25, p, q)) << "the ball is added at 0.5 s";
  ASSERT_TRUE(t.PoseAt(1, 0.75, p, q));
  EXPECT_NEAR(p.x(), 5.5, 1e-12);
  ASSERT_TRUE(t.PoseAt(1, 1.0, p, q));
  EXPECT_EQ(p, RVec3(6, 5, 5));
  EXPECT_FALSE(t.PoseAt(0, 1.5, p, q));
}

TEST(RengineView, TrajectoryRowsNotOfTheFormatAreRefusedByLine) {
  EXPECT_NE(ErrorOf("step,time,body\n").find("t.csv:1: the header"), std::string::npos);
  EXPECT_NE(ErrorOf(kHeader + "0,0,a,0,0,0,1,0,0,0,0,0,0,0,0\n").find("t.csv:2: 15 fields"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHeader + "0,0,a,0,nan,0,1,0,0,0,0,0,0,0,0,0\n").find("t.csv:2: field 5"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHeader + "0,0,a,0,0,0,0,0,0,0,0,0,0,0,0,0\n").find("zero quaternion"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHeader + "1,1,a,0,0,0,1,0,0,0,0,0,0,0,0,0\n0,0,a,0,0,0,1,0,0,0,0,0,0,0,0,0\n")
                .find("t.csv:3: time runs backwards"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHeader).find("no rows"), std::string::npos);
}
