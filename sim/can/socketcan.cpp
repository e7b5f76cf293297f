#include "can/socketcan.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

namespace mcsim {

namespace {

// The command space of the DBC (0x200-0x2FF); the low four bits are the node.
constexpr canid_t kCmdFirst = 0x200;
constexpr canid_t kCmdLast = 0x2FF;
constexpr canid_t kNodeMask = 0xF;

bool send_cb(void* ctx, const hal_can_frame_t* f) { return static_cast<SocketCan*>(ctx)->send(*f); }
bool receive_cb(void* ctx, hal_can_frame_t* f) { return static_cast<SocketCan*>(ctx)->receive(f); }

}  // namespace

SocketCan::SocketCan(const std::string& iface, unsigned node) : iface_(iface)
{
    if (iface.empty() || iface.size() >= IFNAMSIZ) {
        throw std::invalid_argument("--can: '" + iface + "' is not an interface name (1-15 characters)");
    }
    if (node > kNodeMask) {
        throw std::invalid_argument("--can-node: must be 0-15 (got " + std::to_string(node) + ")");
    }
    const unsigned idx = if_nametoindex(iface.c_str());
    if (idx == 0) {
        throw std::invalid_argument("--can: no network interface '" + iface +
                                    "' (create one: ip link add dev " + iface + " type vcan && ip link set up " +
                                    iface + ")");
    }
    fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) {
        const int e = errno;
        throw std::runtime_error("--can " + iface + ": cannot open a CAN socket: " + std::strerror(e) +
                                 (e == EAFNOSUPPORT ? " (this kernel has no SocketCAN: load can and can-raw)" : ""));
    }
    // only our node's commands: id & (0x700 | 0xF) == 0x200 | node covers
    // 0x200-0x2FF of this node
    can_filter flt{};
    flt.can_id = (kCmdFirst | node) & CAN_SFF_MASK;
    flt.can_mask = (CAN_SFF_MASK & ~(kCmdLast - kCmdFirst - kNodeMask)) | CAN_EFF_FLAG | CAN_RTR_FLAG;
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &flt, sizeof flt) != 0) {
        const int e = errno;
        ::close(fd_);
        throw std::runtime_error("--can " + iface + ": CAN_RAW_FILTER: " + std::strerror(e));
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(idx);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        const int e = errno;
        ::close(fd_);
        throw std::invalid_argument("--can: cannot bind to '" + iface + "': " + std::strerror(e) +
                                    " (is it a CAN interface, and up?)");
    }
    bus_.ctx = this;
    bus_.send = &send_cb;
    bus_.receive = &receive_cb;
}

SocketCan::~SocketCan()
{
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

bool SocketCan::send(const hal_can_frame_t& f)
{
    can_frame cf{};
    cf.can_id = f.id & CAN_SFF_MASK;
    cf.can_dlc = f.dlc > 8 ? 8 : f.dlc;
    std::memcpy(cf.data, f.data, cf.can_dlc);
    const ssize_t n = ::write(fd_, &cf, sizeof cf);
    if (n != static_cast<ssize_t>(sizeof cf)) {
        ++send_failures_;
        return false;
    }
    ++sent_;
    return true;
}

bool SocketCan::receive(hal_can_frame_t* f)
{
    can_frame cf{};
    const ssize_t n = ::recv(fd_, &cf, sizeof cf, MSG_DONTWAIT);
    if (n != static_cast<ssize_t>(sizeof cf)) {
        return false;
    }
    ++received_;
    f->id = cf.can_id & CAN_SFF_MASK;
    // an extended or remote frame is handed on with an id the parser refuses
    if ((cf.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) != 0) {
        f->id = 0xFFFFFFFFu;
    }
    f->dlc = cf.can_dlc;
    std::memcpy(f->data, cf.data, sizeof f->data);
    return true;
}

}  // namespace mcsim
