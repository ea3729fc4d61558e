// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Helpers for rostest gtests that check live nodes.
#pragma once

#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <rosgraph_msgs/Log.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <unistd.h>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace efs::rostest {

/// Waits up to `timeout_s` for one message on `topic`; null if none came.
template <typename M>
boost::shared_ptr<const M> waitForMessage(ros::NodeHandle& nh, const std::string& topic,
                                          double timeout_s) {
  return ros::topic::waitForMessage<M>(topic, nh, ros::Duration(timeout_s));
}

/// Waits up to `timeout_wall_s` (wall time) for the first /clock message under use_sim_time.
/// roscpp subscribes to /clock on its own, independently of the test's subscriptions: a message
/// on another topic can arrive while the simulated time still reads zero.
inline bool waitForSimTime(double timeout_wall_s) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_wall_s);
  while (ros::Time::now().isZero()) {
    if (ros::WallTime::now() > deadline) return false;
    ros::WallDuration(0.01).sleep();
  }
  return true;
}

/// True if a node of that name is registered with the master.
inline bool nodeAlive(const std::string& name) {
  std::vector<std::string> nodes;
  ros::master::getNodes(nodes);
  for (const auto& n : nodes) {
    if (n == name) return true;
  }
  return false;
}

/// Waits up to `timeout_wall_s` (wall time) until `publisher` (a full node name, "/player") has an
/// open connection carrying `topic` to `subscriber` ("/lio_bridge"), as the publisher's own bus
/// information says (getBusInfo). The master lists a subscriber before it has connected to the
/// publisher; messages published in between are lost.
inline bool waitForConnection(const std::string& publisher, const std::string& topic,
                              const std::string& subscriber, double timeout_wall_s) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_wall_s);
  while (true) {
    XmlRpc::XmlRpcValue request, response, payload;
    request[0] = ros::this_node::getName();
    request[1] = publisher;
    std::string host;
    uint32_t port = 0;
    if (ros::master::execute("lookupNode", request, response, payload, false) &&
        ros::network::splitURI(static_cast<std::string>(payload), host, port)) {
      XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
      XmlRpc::XmlRpcValue args, info;
      args[0] = ros::this_node::getName();
      // [code, message, [[id, destination, direction, transport, topic, ...], ...]]
      if (client.execute("getBusInfo", args, info) &&
          info.getType() == XmlRpc::XmlRpcValue::TypeArray && info.size() == 3 &&
          static_cast<int>(info[0]) == 1) {
        XmlRpc::XmlRpcValue& links = info[2];
        for (int i = 0; i < links.size(); ++i) {
          if (links[i].size() < 5) continue;
          if (static_cast<std::string>(links[i][2]) == "o" &&
              static_cast<std::string>(links[i][4]) == topic &&
              static_cast<std::string>(links[i][1]) == subscriber) {
            return true;
          }
        }
      }
    }
    if (ros::WallTime::now() > deadline) return false;
    ros::WallDuration(0.05).sleep();
  }
}

/// Collects /rosout messages so tests can check what a node said. (Not /rosout_agg: rostest runs
/// its master without the rosout relay node, so /rosout_agg stays silent.)
class LogCollector {
 public:
  explicit LogCollector(ros::NodeHandle& nh)
      : sub_(nh.subscribe("/rosout", 1000, &LogCollector::onLog, this)) {}

  /// Waits until at least `publishers` nodes are connected to this collector (log lines sent
  /// before a node is connected are lost).
  bool waitForPublishers(uint32_t publishers, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (sub_.getNumPublishers() < publishers && ros::WallTime::now() < end) {
      ros::WallDuration(0.05).sleep();
    }
    return sub_.getNumPublishers() >= publishers;
  }

  /// Waits until a message from `node` containing `needle` arrived, up to `timeout_s`.
  bool waitFor(const std::string& node, const std::string& needle, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      ros::spinOnce();
      for (const auto& m : logs_) {
        if (m.name == node && m.msg.find(needle) != std::string::npos) return true;
      }
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }

 private:
  void onLog(const rosgraph_msgs::Log& m) { logs_.push_back(m); }
  ros::Subscriber sub_;
  std::vector<rosgraph_msgs::Log> logs_;
};

struct NodeRun {
  int exit_code = -1;  ///< the process's exit status, or 128 + signal if it was killed
  std::string output;  ///< stdout and stderr together
};

/// Runs one of this package's node executables to completion (it must stop by itself within
/// `timeout_s`) against the current master, with extra command-line arguments (e.g. private
/// parameters as `_key:=value`). The node executables sit beside this test executable. Private
/// parameters left on the server by an earlier run are deleted first, so runs are independent.
inline NodeRun runNode(const std::string& node, const std::string& args, int timeout_s) {
  ros::param::del("/" + node + "_under_test");
  std::array<char, 4096> self{};
  const ssize_t n = readlink("/proc/self/exe", self.data(), self.size() - 1);
  std::string dir(self.data(), n > 0 ? static_cast<size_t>(n) : 0);
  dir = dir.substr(0, dir.rfind('/'));
  const std::string cmd = "timeout " + std::to_string(timeout_s) + " " + dir + "/" + node +
                          " __name:=" + node + "_under_test " + args + " 2>&1";
  NodeRun run;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 512> buf{};
  while (fgets(buf.data(), buf.size(), pipe)) run.output += buf.data();
  const int status = pclose(pipe);
  if (WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) run.exit_code = 128 + WTERMSIG(status);
  return run;
}

}  // namespace efs::rostest
