// A Modbus RTU slave built on libmodbus (an implementation independent of rtuscope), for
// the live-capture tests: it answers every public read/write function from one register
// map until SIGTERM.
//
//   modbus_test_slave PORT SLAVE_ID BAUD PARITY(N|E|O) STOP_BITS
#include <errno.h>
#include <modbus/modbus.h>
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

volatile sig_atomic_t g_stop = 0;

void on_signal(int) {
  g_stop = 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s PORT SLAVE_ID BAUD PARITY STOP_BITS\n", argv[0]);
    return 2;
  }
  struct sigaction sa {};
  sa.sa_handler = on_signal;  // no SA_RESTART: a blocked receive returns EINTR
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);

  modbus_t* ctx = modbus_new_rtu(argv[1], std::atoi(argv[3]), argv[4][0], 8, std::atoi(argv[5]));
  if (ctx == nullptr || modbus_set_slave(ctx, std::atoi(argv[2])) != 0 ||
      modbus_connect(ctx) != 0) {
    std::fprintf(stderr, "modbus_test_slave: %s: %s\n", argv[1], modbus_strerror(errno));
    return 2;
  }
  modbus_mapping_t* map = modbus_mapping_new(200, 200, 200, 200);
  for (int i = 0; i < 200; ++i) {
    map->tab_registers[i] = static_cast<uint16_t>(1000 + i);
    map->tab_input_registers[i] = static_cast<uint16_t>(2000 + i);
    map->tab_bits[i] = static_cast<uint8_t>(i % 3 == 0);
    map->tab_input_bits[i] = static_cast<uint8_t>(i % 2 == 0);
  }
  std::vector<uint8_t> query(MODBUS_RTU_MAX_ADU_LENGTH);
  std::printf("ready\n");
  std::fflush(stdout);
  while (g_stop == 0) {
    const int rc = modbus_receive(ctx, query.data());
    if (rc > 0) {
      modbus_reply(ctx, query.data(), rc, map);
    } else if (rc == -1 && (errno == EINTR || g_stop != 0)) {
      break;
    }
    // Other errors (bad CRC, another slave's frame) are part of bus life: keep serving.
  }
  modbus_mapping_free(map);
  modbus_close(ctx);
  modbus_free(ctx);
  return 0;
}
