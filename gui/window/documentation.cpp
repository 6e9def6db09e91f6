#include "gui/window/documentation.h"

#include <QCoreApplication>
#include <QDesktopServices>
#include <QDialogButtonBox>
#include <QHBoxLayout>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QTextBlock>
#include <QTextBrowser>
#include <QTextCursor>
#include <QTextDocument>
#include <QVBoxLayout>


namespace linkscape::gui {

namespace {

// The guide's screenshots are full-size window captures: each is shown at
// most `width` pixels wide, so a page needs no sideways scrolling.
void fit_images(QTextDocument* document, int width) {
  for (QTextBlock block = document->begin(); block.isValid(); block = block.next())
    for (auto it = block.begin(); !it.atEnd(); ++it) {
      const QTextFragment fragment = it.fragment();
      QTextImageFormat image = fragment.charFormat().toImageFormat();
      if (!image.isValid()) continue;
      const QImage picture = document->resource(QTextDocument::ImageResource, QUrl(image.name())).value<QImage>();
      if (picture.isNull() || picture.width() <= width) continue;
      image.setWidth(width);
      image.setHeight(double(picture.height()) * width / picture.width());
      QTextCursor cursor(document);
      cursor.setPosition(fragment.position());
      cursor.setPosition(fragment.position() + fragment.length(), QTextCursor::KeepAnchor);
      cursor.setCharFormat(image);
    }
}

}  // namespace

std::filesystem::path documentation_home() {
  const std::filesystem::path installed =
      std::filesystem::path(QCoreApplication::applicationDirPath().toStdString()) / "../share/doc/linkscape/README.md";
  const std::filesystem::path source = std::filesystem::path(LINKSCAPE_SOURCE_DOCS) / "../README.md";
  std::error_code ec;
  for (const auto& page : {installed, source})
    if (std::filesystem::is_regular_file(page, ec)) return std::filesystem::weakly_canonical(page, ec);
  return {};
}

DocumentationBrowser::DocumentationBrowser(const std::filesystem::path& home, QWidget* parent)
    : QDialog(parent), browser_(new QTextBrowser(this)) {
  setObjectName("documentationBrowser");
  setWindowTitle(tr("Linkscape documentation"));
  resize(900, 700);
  browser_->setOpenExternalLinks(true);  // web links in the desktop's browser; pages of the guide in place
  browser_->setSearchPaths({QString::fromStdString(home.parent_path().string())});

  auto* back = new QPushButton(tr("Back"), this);
  auto* forward = new QPushButton(tr("Forward"), this);
  auto* start = new QPushButton(tr("Contents"), this);
  back->setEnabled(false);
  forward->setEnabled(false);
  connect(back, &QPushButton::clicked, browser_, &QTextBrowser::backward);
  connect(forward, &QPushButton::clicked, browser_, &QTextBrowser::forward);
  connect(start, &QPushButton::clicked, browser_, &QTextBrowser::home);
  connect(browser_, &QTextBrowser::backwardAvailable, back, &QPushButton::setEnabled);
  connect(browser_, &QTextBrowser::forwardAvailable, forward, &QPushButton::setEnabled);
  connect(browser_, &QTextBrowser::sourceChanged, this, [this] {
    fit_images(browser_->document(), 760);
    setWindowTitle(tr("Linkscape documentation"));
  });

  auto* buttons = new QHBoxLayout;
  buttons->addWidget(back);
  buttons->addWidget(forward);
  buttons->addWidget(start);
  buttons->addStretch();
  auto* close = new QDialogButtonBox(QDialogButtonBox::Close, this);
  connect(close, &QDialogButtonBox::rejected, this, &QDialog::close);
  buttons->addWidget(close);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(browser_);
  layout->addLayout(buttons);
  browser_->setSource(QUrl::fromLocalFile(QString::fromStdString(home.string())), QTextDocument::MarkdownResource);
}

void show_documentation(QWidget* parent) {
  if (auto* open = parent->findChild<DocumentationBrowser*>()) {
    open->show();
    open->raise();
    return;
  }
  const std::filesystem::path home = documentation_home();
  if (home.empty()) {
    QMessageBox::information(parent, QObject::tr("Documentation"),
                             QObject::tr("No copy of the guide is installed. Run 'man linkscape' for every command "
                                         "and option, and 'linkscape --help' for a summary."));
    return;
  }
  auto* browser = new DocumentationBrowser(home, parent);
  browser->show();
}

namespace {

void add_rows(const QMenu* menu, const QString& path, QStringList& rows) {
  for (const QAction* action : menu->actions()) {
    const QString name = path + " > " + action->text().remove('&');
    if (action->menu()) add_rows(action->menu(), name, rows);
    else if (!action->shortcut().isEmpty())
      rows << name + "\t" + QKeySequence::listToString(action->shortcuts(), QKeySequence::NativeText);
  }
}

}  // namespace

QString shortcut_table(const QMenuBar* menus) {
  QStringList rows;
  for (const QAction* action : menus->actions())
    if (action->menu()) add_rows(action->menu(), action->text().remove('&'), rows);
  // Aligned in two columns for the terminal and the dialog alike.
  qsizetype width = 0;
  for (const QString& row : rows) width = std::max(width, row.indexOf('\t'));
  QString table;
  for (const QString& row : rows) {
    const qsizetype tab = row.indexOf('\t');
    table += row.left(tab).leftJustified(width + 3) + row.mid(tab + 1) + "\n";
  }
  return table;
}

void show_shortcuts(QWidget* parent, const QMenuBar* menus) {
  QMessageBox box(parent);
  box.setWindowTitle(QObject::tr("Keyboard shortcuts"));
  box.setText(QObject::tr("Keyboard shortcuts"));
  box.setInformativeText("<pre>" + shortcut_table(menus).toHtmlEscaped() + "</pre>");
  box.exec();
}

}  // namespace linkscape::gui
