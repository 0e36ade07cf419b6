// The host-common library; its sources arrive with the calibration engine.
namespace odocal::host {
int host_common_anchor() { return 0; }
}  // namespace odocal::host
