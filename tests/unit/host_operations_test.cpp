// The markers of host operations in the cores' messages (errors/host_operations.h).
#include "errors/host_operations.h"

#include <gtest/gtest.h>

#include <string>

namespace {

std::string bracketed(const std::string& name) { return "<" + name + ">"; }

TEST(HostOperations, EveryMarkerIsReplacedAndTheRestKept) {
    EXPECT_EQ(rad::expandHostOperations("run {{Remove Zero Area Faces}} and {{Re-Compute Vertex Normals}}.", bracketed),
              "run <Remove Zero Area Faces> and <Re-Compute Vertex Normals>.");
    EXPECT_EQ(rad::expandHostOperations("{{A}}{{B}}", bracketed), "<A><B>");
}

TEST(HostOperations, TextWithoutACompleteMarkerIsUnchanged) {
    EXPECT_EQ(rad::expandHostOperations("no marker here", bracketed), "no marker here");
    EXPECT_EQ(rad::expandHostOperations("an open {{ without a close", bracketed), "an open {{ without a close");
    EXPECT_EQ(rad::expandHostOperations("", bracketed), "");
    EXPECT_EQ(rad::expandHostOperations("a single } brace {", bracketed), "a single } brace {");
}

TEST(HostOperations, PlainFormNamesMeshLab) {
    EXPECT_EQ(rad::plainHostOperations("scale it ({{Transform: Scale, Normalize}})"),
              "scale it (MeshLab's Transform: Scale, Normalize)");
}

}  // namespace
